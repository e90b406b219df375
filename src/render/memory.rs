//! What the renderer holds and has created: GPU memory by part ([`MemoryReport`]) and GPU states by kind
//! ([`Creations`]).

/// GPU memory held by the renderer, by part.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MemoryReport {
    pub geometry: u64,
    pub light_depth_maps: u64,
    pub shadow_map: u64,
    /// The colour and depth images and the eye transparency technique's targets.
    pub eye_targets: u64,
    /// The technique whose targets are held (the last frame's), and their part of `eye_targets`.
    pub transparency_name: &'static str,
    pub transparency_targets: u64,
    /// The method whose state is held (the last frame's), and its maps: those it owns, and the shared
    /// light-depth maps its lookup reads (already counted in `light_depth_maps`).
    pub method_name: &'static str,
    pub method_owned: u64,
    pub method_shared: u64,
    /// What the method builds its maps from each frame (`MethodGpu::build_bytes`).
    pub method_build: u64,
    /// The exact reference's fragment lists, when the inspector or a measurement has read them.
    pub reference_lists: u64,
    /// The compute rasteriser's fragment stream, counts and tile lists (`render.raster = compute`).
    pub raster_stream: u64,
}

impl MemoryReport {
    /// Everything the renderer holds (the shared maps once).
    pub fn total(&self) -> u64 {
        self.geometry
            + self.light_depth_maps
            + self.shadow_map
            + self.eye_targets
            + self.method_owned
            + self.method_build
            + self.reference_lists
            + self.raster_stream
    }

    /// What the method costs, as the papers count it: its own maps and the shared ones it reads.
    pub fn method(&self) -> u64 {
        self.method_owned + self.method_shared
    }
}

/// GPU states a renderer has created, by kind: what a frame after [`Renderer::update_points`] must not add to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Creations {
    /// Scene uploads (buffers created from a scene).
    pub scene_uploads: u64,
    /// Shadow-method GPU states (each holds the method's maps and pipelines).
    pub method_states: u64,
    /// Eye transparency technique GPU states.
    pub technique_states: u64,
    /// Pipelines built by the eye passes' caches (meshes and hair, per method and technique).
    pub pipelines: u64,
}
