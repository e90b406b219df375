//! The GPU side shared by every method that stores `K` values per texel in array layers: Opacity Shadow Maps
//! (`K` slices over the whole light range), Deep Opacity Maps and Bounding Opacity Maps (`K` layers placed per
//! texel from the shared near/far maps), Fourier opacity maps (`2K + 1` Fourier coefficients) and moment shadow
//! maps (the power moments). Each keeps only its shader, its uniforms and its setup; the map, the pipelines and
//! the passes are here.
//!
//! Layout: an [`ArrayMap`] of `ceil(K / 4)` layers (4 values per texel). Two builds fill it
//! ([`LayerBuild`], the `build` parameter of OSM, DOM and BOM; the CPU side is `visibility::opacity_layers`):
//!
//! - **targets** (every method): RGBA32F layers written by `ceil(layers / 8)` geometry passes of at most 8
//!   colour targets with additive blending; pass `p` draws with instance index `p` so that the shader knows
//!   which targets it writes (`fs_main`).
//! - **atomic** (the opacity-layer family, one entry per fragment): ONE geometry pass (`fs_count`, through the
//!   shared light vertex stage) in which each fragment adds its u32 fixed-point optical depth to the counter of
//!   its `(texel, entry)` in storage buffers (4 bytes per entry and texel, build memory, laid out as
//!   [`CounterLayout`]: runs of up to [`RESOLVE_RUN`] entries holding a texel's counters side by side, whole
//!   runs per storage binding, up to [`COUNTER_PAGES`] bindings per pass), then a compute resolve
//!   (`shaders/layer_resolve.wgsl`, one invocation per texel, one dispatch per run) that sums an occupied
//!   texel's counters front to back into the map, written as a storage texture in the `storage` parameter's
//!   format: RGBA32F, RGBA16F or RGBA8 unorm (4, 2 or 1 bytes per entry). Each texel's count of leading
//!   all-zero layers is kept, and its flat tail (where every layer holds one sum, the total behind its last
//!   fragment: [`TAIL_BYTES`] per texel): a layer zero again in front, or holding the tail's sum again within
//!   it, is not stored: an empty texel costs nothing once cleared, an occupied one lit as in the frame before
//!   skips the layers in front of its first fragment and behind its last. OSM-256 at 512² (256 MiB of
//!   counters) counts in one pass over two of lavapipe's 128 MiB bindings; beyond four bindings the entries are built in bands of whole runs (one geometry pass each), the
//!   running sum carried across; a map whose run of 4 entries alone exceeds a binding (above 2896² at 128 MiB)
//!   is refused with an error naming the `build` parameter.
//!
//! The light pass's group 1 is the uniform (binding 0), the near (1) and far (2) light-depth maps, and for the
//! atomic build the counters' pages (3, 5, 6, 7) and [`LayerBuildUniforms`] (4); the lookup's group 1 is the
//! array view (0) and the uniform (1).

use super::{MethodContext, MethodGpu, ParamKind, ParamSpec, ParamValues, UniformMirror, choice, value};
use crate::gpu::GpuError;
use crate::gpu::timing::{GpuTimer, Phase};
use crate::render::caster::draw_casters;
use crate::render::maps::{
    AdditivePipelines, ArrayMap, LOOKUP_STAGES, texture_entry, uniform_buffer, uniform_entry,
};
pub use crate::visibility::opacity_layers::{LayerBuild, LayerStorage};
mod atomic;

use atomic::{
    AtomicBuffers, AtomicPipelines, RESOLVE_WORKGROUP, atomic_buffers, atomic_pipelines, resolve_pipeline,
    storage_limit,
};
pub use atomic::{
    COUNTER_PAGES, CounterLayout, RESOLVE_RUN, ResolveDispatch, ResolvePart, TAIL_BYTES, resolve_dispatches,
    resolve_part_mirror,
};
use bytemuck::{Pod, Zeroable};

/// Values one array layer holds.
pub const VALUES_PER_LAYER: u32 = 4;

/// Entries one geometry pass of the colour-target build writes (8 RGBA32F targets).
pub const ENTRIES_PER_TARGETS_PASS: u32 = VALUES_PER_LAYER * AdditivePipelines::MAX_TARGETS;

/// Most entries `build = auto` gives to the colour targets (one geometry pass).
pub const AUTO_TARGETS_MAX_ENTRIES: u32 = ENTRIES_PER_TARGETS_PASS;

/// The `build` parameter of the opacity-layer family. `auto` takes the colour targets up to
/// [`AUTO_TARGETS_MAX_ENTRIES`] entries with f32 storage, the atomic build otherwise: measured on lavapipe
/// (docs/design.md), one target pass costs 0.85–0.9 times the atomic count pass plus its resolve (OSM-16,
/// DOM-3, BOM-4); two (OSM-64) cost 1.3 times as much, eight (OSM-256) 1.9 times.
pub const BUILD: ParamSpec = ParamSpec {
    key: "build",
    label: "build",
    help: "how the layers are filled: atomic = one geometry pass adding fixed-point optical depth to \
           per-(texel, entry) counters with storage atomics, then a resolve into the storage format; \
           targets = additive blending into RGBA32F colour targets, 32 entries per geometry pass; auto = targets \
           up to 32 entries with f32 storage, else atomic",
    kind: ParamKind::Choice {
        options: &["auto", "atomic", "targets"],
    },
    default: 0.0,
};

/// The `storage` parameter: what one entry of the map takes with the atomic build (the colour-target build
/// always stores f32).
pub const STORAGE: ParamSpec = ParamSpec {
    key: "storage",
    label: "storage",
    help: "bytes per stored entry with build = atomic: f32 = 4, f16 = 2 (11 significant bits), u8 = 1 (optical \
           depth in steps of 1/32, saturating at 7.97); build = targets always stores f32",
    kind: ParamKind::Choice {
        options: &["f32", "f16", "u8"],
    },
    default: 0.0,
};

/// The build `values` choose for a map of `entries` entries per texel.
pub fn build(values: &ParamValues, entries: u32) -> LayerBuild {
    let storage = LayerStorage::ALL
        .get(value(values, &STORAGE) as usize)
        .copied()
        .unwrap_or_default();
    match choice(values, &BUILD) {
        "atomic" => LayerBuild::Atomic(storage),
        "targets" => LayerBuild::Targets,
        _ if entries > AUTO_TARGETS_MAX_ENTRIES || storage != LayerStorage::F32 => {
            LayerBuild::Atomic(storage)
        }
        _ => LayerBuild::Targets,
    }
}

/// What the lookup multiplies a stored value by (the methods' uniform field `unit`).
pub fn unit(build: LayerBuild) -> f32 {
    match build {
        LayerBuild::Targets => 1.0,
        LayerBuild::Atomic(s) => s.unit(),
    }
}

/// The map's texel format for `build`.
pub fn map_format(build: LayerBuild) -> wgpu::TextureFormat {
    match build {
        LayerBuild::Targets | LayerBuild::Atomic(LayerStorage::F32) => wgpu::TextureFormat::Rgba32Float,
        LayerBuild::Atomic(LayerStorage::F16) => wgpu::TextureFormat::Rgba16Float,
        LayerBuild::Atomic(LayerStorage::U8) => wgpu::TextureFormat::Rgba8Unorm,
    }
}

/// What tells one layered method's GPU side from another's.
pub struct LayerMethod<U> {
    /// Method name, for labels (`hairlab.<name>.<resource>`) and timings.
    pub name: &'static str,
    /// What a stored value is called in pass timings (`slices`, `layers`).
    pub unit: &'static str,
    /// The light-pass shader: `vs_main`, `fs_main` writing up to 8 RGBA32F outputs, and `fs_count` (the
    /// atomic build, `common/layer_pass.wgsl`) for the methods whose setup may ask for it.
    pub shader: &'static str,
    pub setup: fn(&ParamValues) -> LayerSetup<U>,
}

/// What a layered method needs for some parameter values.
pub struct LayerSetup<U> {
    /// Stored values per texel, `K >= 1`.
    pub values: u32,
    /// Shared light-depth maps (4 bytes per texel each) the lookup reads: counted in the method's memory, and
    /// reported as shared.
    pub depth_maps: u32,
    /// How the map is filled ([`LayerBuild::Targets`] for methods without `fs_count`).
    pub build: LayerBuild,
    /// Read by both the light pass and the lookup.
    pub uniforms: U,
}

/// Mirrors `LayerBuildUniforms` in `shaders/common/layer_build_uniforms.wgsl` (the atomic build's count and
/// resolve passes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct LayerBuildUniforms {
    pub resolution: u32,
    pub entries: u32,
    /// Entries per band (one geometry pass): all of them, or a multiple of `run`.
    pub band: u32,
    /// 0 f32, 1 f16, 2 u8.
    pub storage: u32,
    /// Entries per run of counters ([`CounterLayout::run`]).
    pub run: u32,
    /// Whole runs per page ([`CounterLayout::runs_per_page`]).
    pub runs_per_page: u32,
    pub pad0: u32,
    pub pad1: u32,
}

/// The WGSL mirror of [`LayerBuildUniforms`], for the layout test.
pub fn build_uniforms_mirror() -> UniformMirror {
    crate::uniform_mirror!(
        "LayerBuildUniforms",
        LayerBuildUniforms {
            resolution,
            entries,
            band,
            storage,
            run,
            runs_per_page,
            pad0,
            pad1
        }
    )
}

/// The light pass's group 1, for the light-depth maps it was made with.
struct PassBindGroup {
    near: wgpu::TextureView,
    far: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
}

/// The maps for one parameter set and resolution, with the lookup's bind group.
struct Maps {
    map: ArrayMap,
    lookup_bind_group: wgpu::BindGroup,
    /// The atomic build's resolve group over the map as a storage texture, made on first use.
    resolve_bind_group: Option<wgpu::BindGroup>,
}

/// GPU state of a layered method; created with its maps for the current parameters, so it always has them.
pub struct LayersGpu<U> {
    method: LayerMethod<U>,
    pass_layout: wgpu::BindGroupLayout,
    lookup_layout: wgpu::BindGroupLayout,
    module: wgpu::ShaderModule,
    pipelines: AdditivePipelines,
    uniforms: wgpu::Buffer,
    pass_bind_group: PassBindGroup,
    maps: Maps,
    atomic: Option<AtomicPipelines>,
    buffers: Option<AtomicBuffers>,
    setup: LayerSetup<U>,
}

impl<U: Pod + Send> LayersGpu<U> {
    /// Creates the state and allocates the maps for `ctx`'s parameters and map resolution.
    pub fn create(ctx: &MethodContext, method: LayerMethod<U>) -> Result<LayersGpu<U>, GpuError> {
        let device = &ctx.gpu.device;
        let name = method.name;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let pass_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(&format!("hairlab.{name}.pass_layout")),
            entries: &[
                uniform_entry(0, frag),
                texture_entry(1, frag, wgpu::TextureViewDimension::D2),
                texture_entry(2, frag, wgpu::TextureViewDimension::D2),
            ],
        });
        let lookup_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(&format!("hairlab.{name}.lookup_layout")),
            entries: &[
                texture_entry(0, LOOKUP_STAGES, wgpu::TextureViewDimension::D2Array),
                uniform_entry(1, LOOKUP_STAGES),
            ],
        });
        let uniforms = uniform_buffer::<U>(device, &format!("{name}.uniforms"));
        let module = ctx
            .light
            .module(device, &format!("hairlab.{name}.shader"), method.shader);
        let pipelines = AdditivePipelines::new(
            name,
            ctx.light,
            &[ctx.frame_layout, &pass_layout],
            module.clone(),
            "fs_main",
        );
        let setup = (method.setup)(ctx.values);
        let pass_bind_group = pass_bind_group(ctx, name, &pass_layout, &uniforms);
        let maps = make_maps(ctx, name, &lookup_layout, &uniforms, &setup)?;
        let mut gpu = LayersGpu {
            method,
            pass_layout,
            lookup_layout,
            module,
            pipelines,
            uniforms,
            pass_bind_group,
            maps,
            atomic: None,
            buffers: None,
            setup,
        };
        gpu.prepare_atomic(ctx)?;
        Ok(gpu)
    }

    /// Makes the atomic build's pipelines and buffers when the setup asks for that build and they are missing
    /// or stale; drops the buffers otherwise.
    fn prepare_atomic(&mut self, ctx: &MethodContext) -> Result<(), GpuError> {
        let LayerBuild::Atomic(storage) = self.setup.build else {
            self.buffers = None;
            return Ok(());
        };
        let name = self.method.name;
        let resolution = ctx.map_resolution();
        let entries = self.setup.values;
        let layout = match CounterLayout::new(name, resolution, entries, storage_limit(ctx.gpu)) {
            Ok(layout) => layout,
            Err(e) => {
                self.buffers = None;
                return Err(e);
            }
        };
        let atomic = match &mut self.atomic {
            Some(a) => a,
            slot => slot.insert(atomic_pipelines(ctx, name, &self.module, ctx.frame_layout)),
        };
        let views = (&ctx.light_maps.near_view, &ctx.light_maps.far_view);
        let stale = self.buffers.as_ref().is_none_or(|b| {
            b.resolution != resolution
                || b.entries != entries
                || b.layout != layout
                || b.near != *views.0
                || b.far != *views.1
        });
        if stale {
            self.buffers = None;
            self.buffers = Some(atomic_buffers(
                ctx,
                name,
                atomic,
                &self.uniforms,
                (resolution, entries, layout),
            )?);
        }
        let format = self.maps.map.format;
        let map_layout = &resolve_pipeline(&ctx.gpu.device, name, atomic, format).map_layout;
        if self.maps.resolve_bind_group.is_none() {
            if let Some(b) = &mut self.buffers {
                b.tails_stale = true;
            }
            self.maps.resolve_bind_group =
                Some(ctx.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&format!("hairlab.{name}.resolve_map_bind_group")),
                    layout: map_layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&self.maps.map.array_view),
                    }],
                }));
        }
        let u = LayerBuildUniforms {
            resolution,
            entries,
            band: layout.band,
            storage: LayerStorage::ALL.iter().position(|s| *s == storage).unwrap_or(0) as u32,
            run: layout.run,
            runs_per_page: layout.runs_per_page,
            pad0: 0,
            pad1: 0,
        };
        ctx.gpu
            .queue
            .write_buffer(&atomic.uniforms, 0, bytemuck::bytes_of(&u));
        Ok(())
    }

    /// Records the atomic build: per band, the counting geometry pass and the resolve dispatch of its entries.
    fn record_atomic(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        let (name, unit) = (self.method.name, self.method.unit);
        if let Some(b) = self.buffers.as_mut().filter(|b| b.tails_stale) {
            encoder.clear_buffer(&b.tails, 0, None);
            b.tails_stale = false;
        }
        let (Some(atomic), Some(buffers), Some(map_group)) = (
            self.atomic.as_ref(),
            self.buffers.as_ref(),
            self.maps.resolve_bind_group.as_ref(),
        ) else {
            return;
        };
        let map = &self.maps.map;
        let Some(pipeline) = atomic.resolve.iter().find(|r| r.format == map.format) else {
            return;
        };
        let pipeline = &pipeline.pipeline;
        let values = self.setup.values;
        let band = buffers.layout.band;
        for b in 0..values.div_ceil(band) {
            let first = b * band;
            let end = (first + band).min(values);
            let ts = timer
                .as_mut()
                .and_then(|t| t.pass(Phase::Method, format!("{name}: count {unit} {first}-{}", end - 1)));
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&format!("hairlab.{name}.count")),
                color_attachments: &[buffers.null_target.attachment()],
                depth_stencil_attachment: None,
                timestamp_writes: ts,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            draw_casters(
                &mut pass,
                &atomic.count[buffers.layout.count_pipeline()],
                ctx.frame_bind_group,
                Some(&buffers.pass_bind_group),
                ctx.casters,
                b..b + 1,
            );
            drop(pass);
            let ts = timer.as_mut().and_then(|t| {
                t.compute_pass(
                    encoder,
                    Phase::Method,
                    format!("{name}: resolve {unit} {first}-{}", end - 1),
                )
            });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(&format!("hairlab.{name}.resolve")),
                timestamp_writes: ts,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(1, map_group, &[]);
            let runs = buffers
                .dispatches
                .iter()
                .enumerate()
                .filter(|(_, d)| d.band_first == first);
            for (i, d) in runs {
                let offset = i as u32 * buffers.part_stride;
                pass.set_bind_group(0, &buffers.resolve_bind_groups[d.page], &[offset]);
                pass.dispatch_workgroups(map.resolution.div_ceil(RESOLVE_WORKGROUP), map.resolution, 1);
            }
        }
    }

    /// Records the colour-target build: `ceil(layers / 8)` additive geometry passes.
    fn record_targets(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        let (name, unit) = (self.method.name, self.method.unit);
        let layers = self.maps.map.layers;
        let values = self.setup.values;
        let per_pass = AdditivePipelines::MAX_TARGETS;
        for p in 0..layers.div_ceil(per_pass) {
            let first = p * per_pass;
            let count = (layers - first).min(per_pass);
            let pipeline = self.pipelines.get(&ctx.gpu.device, count);
            let attachments = self.maps.map.attachments(first, count);
            let last = ((first + count) * VALUES_PER_LAYER).min(values) - 1;
            let ts = timer.as_mut().and_then(|t| {
                t.pass(
                    Phase::Method,
                    format!("{name}: {unit} {}-{last}", first * VALUES_PER_LAYER),
                )
            });
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(&format!("hairlab.{name}.pass")),
                color_attachments: &attachments,
                depth_stencil_attachment: None,
                timestamp_writes: ts,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            draw_casters(
                &mut pass,
                pipeline,
                ctx.frame_bind_group,
                Some(&self.pass_bind_group.bind_group),
                ctx.casters,
                p..p + 1,
            );
        }
    }
}

/// Array layers holding `values` values.
fn layers_for(values: u32) -> u32 {
    values.max(1).div_ceil(VALUES_PER_LAYER)
}

fn make_maps<U>(
    ctx: &MethodContext,
    name: &str,
    lookup_layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
    setup: &LayerSetup<U>,
) -> Result<Maps, GpuError> {
    let map = ArrayMap::with_format(
        ctx.gpu,
        &format!("{name}.layers"),
        ctx.map_resolution(),
        layers_for(setup.values),
        map_format(setup.build),
    )?;
    let lookup_bind_group = ctx.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(&format!("hairlab.{name}.lookup_bind_group")),
        layout: lookup_layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&map.array_view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: uniforms.as_entire_binding(),
            },
        ],
    });
    Ok(Maps {
        map,
        lookup_bind_group,
        resolve_bind_group: None,
    })
}

fn pass_bind_group(
    ctx: &MethodContext,
    name: &str,
    layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
) -> PassBindGroup {
    let (near, far) = (&ctx.light_maps.near_view, &ctx.light_maps.far_view);
    let bind_group = ctx.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(&format!("hairlab.{name}.pass_bind_group")),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(near),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(far),
            },
        ],
    });
    PassBindGroup {
        near: near.clone(),
        far: far.clone(),
        bind_group,
    }
}

impl<U: Pod + Send> MethodGpu for LayersGpu<U> {
    fn prepare(&mut self, ctx: &MethodContext, _timer: &mut Option<GpuTimer>) -> Result<(), GpuError> {
        let name = self.method.name;
        self.setup = (self.method.setup)(ctx.values);
        let layers = layers_for(self.setup.values);
        let m = &self.maps.map;
        if m.resolution != ctx.map_resolution()
            || m.layers != layers
            || m.format != map_format(self.setup.build)
        {
            self.maps = make_maps(ctx, name, &self.lookup_layout, &self.uniforms, &self.setup)?;
        }
        let p = &self.pass_bind_group;
        if p.near != ctx.light_maps.near_view || p.far != ctx.light_maps.far_view {
            self.pass_bind_group = pass_bind_group(ctx, name, &self.pass_layout, &self.uniforms);
        }
        self.prepare_atomic(ctx)?;
        ctx.gpu
            .queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&self.setup.uniforms));
        Ok(())
    }

    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        match self.setup.build {
            LayerBuild::Targets => self.record_targets(ctx, encoder, timer),
            LayerBuild::Atomic(_) => self.record_atomic(ctx, encoder, timer),
        }
    }

    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.lookup_layout
    }

    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.maps.lookup_bind_group
    }

    fn memory_bytes(&self) -> u64 {
        self.maps.map.bytes() + self.shared_bytes()
    }

    fn shared_bytes(&self) -> u64 {
        let r = self.maps.map.resolution as u64;
        r * r * self.setup.depth_maps as u64 * 4
    }

    /// The atomic build's counters, running sums and null target.
    fn build_bytes(&self) -> u64 {
        self.buffers.as_ref().map_or(0, AtomicBuffers::bytes)
    }

    fn geometry_passes(&self) -> u32 {
        match (&self.buffers, self.setup.build) {
            (Some(b), LayerBuild::Atomic(_)) => self.setup.values.div_ceil(b.layout.band),
            _ => self.maps.map.layers.div_ceil(AdditivePipelines::MAX_TARGETS),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn storage_options_are_the_storages_in_order() {
        let names: Vec<&str> = LayerStorage::ALL.iter().map(|s| s.name()).collect();
        assert_eq!(STORAGE.options(), names.as_slice());
        for (i, s) in LayerStorage::ALL.into_iter().enumerate() {
            let values =
                |b: f32| ParamValues::from([("build".to_string(), b), ("storage".to_string(), i as f32)]);
            assert_eq!(build(&values(1.0), 4), LayerBuild::Atomic(s));
            assert_eq!(build(&values(2.0), 4), LayerBuild::Targets);
        }
        assert_eq!(BUILD.option(2.0), Some("targets"));
    }

    #[test]
    fn auto_takes_the_targets_up_to_one_pass_of_f32_and_the_atomic_build_otherwise() {
        let none = ParamValues::new();
        assert_eq!(build(&none, 1), LayerBuild::Targets);
        assert_eq!(build(&none, 32), LayerBuild::Targets);
        assert_eq!(build(&none, 33), LayerBuild::Atomic(LayerStorage::F32));
        assert_eq!(build(&none, 64), LayerBuild::Atomic(LayerStorage::F32));
        assert_eq!(build(&none, 256), LayerBuild::Atomic(LayerStorage::F32));
        let u8 = ParamValues::from([("storage".to_string(), 2.0)]);
        assert_eq!(build(&u8, 3), LayerBuild::Atomic(LayerStorage::U8));
    }
}
