//! Hybrid fur's typed per-pixel lists (Andersen et al. 2016 §3.3 and §4; spec B.7), an eye transparency
//! technique: the guard hairs' shaded fragments (explicit, on camera-facing ribbons, B.6) and the shell pass's
//! ray-marched fragments (shell, or virtual: one per group of march steps) pushed onto per-pixel lists
//! ([`PixelLists`], the exact reference's), then sorted and blended back to front by the typed resolve
//! (`shaders/fur/resolve.wgsl`, CPU model [`crate::fur::blend`]). The meshes are not stored: they are drawn
//! first, every list pass tests their depth by hand and their colour is what the resolve blends onto (B.7; the
//! paper stores base-mesh fragments, Table 1 row 5).
//!
//! Passes: the shell's count (the march run once to count what it emits) and the strands' count, one
//! readback, the node buffer sized to exactly the frame's fragments (bands of rows when they exceed a
//! binding), then per band the strands' fill, the shell's fill and the resolve. The technique owns the shell's
//! GPU state, built from the scene's fur ([`SceneFur`]) when its generation changes; without fur it draws the
//! guard hairs alone, whose typed lists every blending composites exactly.

use crate::fur::blend::Typed;
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings::Binding;
use crate::render::eye::lists::{self, BAND_KIB, ListNames, ListSpec, NODE_BYTES, PixelLists};
use crate::render::eye::pipelines;
use crate::render::geometry::RIBBON_GROUP;
use crate::render::method::{ParamValues, Role, UniformMirror};
use crate::render::transparency::{
    EyeFrame, EyeSetup, EyeTransparency, HairEntry, HairGeometry, TechniqueInfo, TransparencyGpu,
};
use crate::transparency::{Compositor, ModelContext};

pub use super::held::FurResolveUniforms;
use super::held::{HeldFur, typed_fragments};
pub use super::state::FurListStats;
use super::state::{FurLists, FurState};

/// The guard hairs' fill: the exact reference's list push, on camera-facing ribbons (B.6).
static FILL: HairEntry = lists::fill_entry(HairGeometry::Ribbons);

static INFO: TechniqueInfo = TechniqueInfo {
    name: "fur",
    label: "Fur: typed lists",
    paper: "Andersen, Falster, Frisvad, Christensen 2016, Hybrid fur rendering: combining volumetric fur with \
            explicit hair strands (§3.3, §4)",
    role: Role::Reference,
    hair_wgsl: lists::FILL_WGSL,
    hair_entries: std::slice::from_ref(&FILL),
    pass_wgsl: &["fur/ribbon_count.wgsl", "fur/resolve.wgsl"],
    params: &[BAND_KIB],
    color: [150, 95, 60],
    // f32 front-to-back sums in both; measured in tests/it/fur_typed.rs.
    gpu_tolerance: 1e-5,
};

/// The technique that shows a scene's fur.
pub struct FurTechnique;

impl EyeTransparency for FurTechnique {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn shows_fur(&self) -> bool {
        true
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(FurGpu::new(setup)?))
    }

    /// Without a shell the typed lists hold strand fragments only and every blending is the exact composite.
    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(crate::transparency::exact::ExactParams)
    }

    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "FurResolveUniforms",
            FurResolveUniforms {
                blending,
                attenuation,
                view,
                deepest
            }
        ))
    }
}

pub struct FurGpu {
    lists: PixelLists,
    /// The guard hairs' count pass over their ribbons (`fur/ribbon_count.wgsl`).
    count_pipeline: wgpu::RenderPipeline,
    frame_layout: wgpu::BindGroupLayout,
    uniforms: wgpu::Buffer,
    /// The shell count's total, copied before the strands add theirs.
    shell_total: wgpu::Buffer,
    /// The scene's fur: its shell, settings and march.
    fur: HeldFur,
    stats: FurListStats,
    /// Whether a frame has been drawn (its lists can be read).
    drawn: bool,
}

impl FurGpu {
    fn new(setup: &EyeSetup) -> Result<FurGpu, GpuError> {
        let device = &setup.gpu.device;
        let lists = PixelLists::new(
            setup.gpu,
            setup.frame_layout,
            (setup.width, setup.height),
            ListSpec {
                label: "fur",
                what: "fur lists",
                resolve_wgsl: INFO.pass_wgsl[1],
                resolve_extra: &[Binding::Uniform],
            },
        )?;
        let count_pipeline = pipelines::storage_pass(
            device,
            "hairlab.fur.ribbon_count",
            INFO.pass_wgsl[0],
            [setup.frame_layout, lists.count_layout()],
            HairGeometry::Ribbons,
        );
        let mut gpu = FurGpu {
            lists,
            count_pipeline,
            frame_layout: setup.frame_layout.clone(),
            uniforms: crate::render::eye::bindings::uniform(
                device,
                "hairlab.fur.resolve_uniforms",
                std::mem::size_of::<FurResolveUniforms>() as u64,
            ),
            shell_total: crate::render::eye::bindings::storage(device, "hairlab.fur.shell_total", 4),
            fur: HeldFur::default(),
            stats: FurListStats::default(),
            drawn: false,
        };
        gpu.update(setup)?;
        Ok(gpu)
    }
}

impl FurLists for FurGpu {
    fn stats(&self) -> FurListStats {
        self.stats
    }

    fn typed_lists(&self, gpu: &Gpu) -> Result<Vec<Vec<Typed>>, GpuError> {
        Ok(self.lists.read(gpu)?.into_iter().map(typed_fragments).collect())
    }
}

impl TransparencyGpu for FurGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        self.lists.resize(gpu, width, height)
    }

    fn update(&mut self, setup: &EyeSetup) -> Result<(), GpuError> {
        self.resize(setup.gpu, setup.width, setup.height)?;
        self.fur.sync(setup.gpu, &self.frame_layout, setup.scene_fur)
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let (width, height) = self.lists.size();
        let pixels = width as u64 * height as u64;
        let mode = self.fur.settings.mode;
        let held = self.fur.shell.as_ref().map(|s| &s.gpu);
        let shell = held.filter(|_| mode.shell());
        // Without fur the guard hairs are all there is.
        let strands = (self.fur.shell.is_none() || mode.strands()) && frame.geometry.hair_index_count > 0;
        let gpu = frame.gpu;
        let device = &gpu.device;
        self.fur.light(&gpu.queue, frame.light);
        // Counts: the shell's first (its total copied aside), then the strands'.
        let counts = self.lists.clear_counts(&mut frame.encoder);
        if let Some(held) = held {
            held.reset_stats(&mut frame.encoder);
        }
        if let Some(shell) = shell {
            let timestamps = frame
                .timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::FurShell, "fur: shell count"));
            shell.record_count(
                gpu,
                &mut frame.encoder,
                frame.frame_bind_group,
                counts,
                &frame.targets.depth_view,
                &frame.targets.null_view,
                timestamps,
                None,
            );
        }
        frame
            .encoder
            .copy_buffer_to_buffer(counts, pixels * 4, &self.shell_total, 0, 4);
        if strands {
            let ribbons = frame.geometry.ribbons()?;
            let count_group = self.lists.count_group(device, &frame.targets.depth_view);
            let timestamps = frame
                .timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::EyeHair, "fur: explicit count"));
            let mut pass = frame.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("hairlab.fur.count_pass"),
                color_attachments: &[frame.targets.null_attachment()],
                depth_stencil_attachment: None,
                timestamp_writes: timestamps,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.count_pipeline);
            pass.set_bind_group(0, frame.frame_bind_group, &[]);
            pass.set_bind_group(1, &count_group, &[]);
            pass.set_bind_group(RIBBON_GROUP, ribbons, &[]);
            pass.draw(0..frame.geometry.ribbon_vertex_count(), 0..1);
        }
        frame.flush();
        let shell_total: Vec<u32> =
            bytemuck::pod_collect_to_vec(&crate::gpu::readback::copy_out(gpu, &self.shell_total)?);
        let plan = self
            .lists
            .plan(
                gpu,
                frame.output.1,
                crate::render::method::value(frame.values, &INFO.params[0]) as u64 * 1024,
                &ListNames {
                    deep: "fur.group_steps: the fur lists",
                    rows: "the fur lists'",
                    drawn: String::new(),
                },
            )?
            .clone();
        gpu.queue.write_buffer(
            &self.uniforms,
            0,
            bytemuck::bytes_of(&FurResolveUniforms::new(&self.fur.settings, plan.deepest)),
        );
        self.stats = FurListStats {
            explicit: plan.fragments - u64::from(shell_total[0]),
            shell: u64::from(shell_total[0]),
            deepest: plan.deepest,
            bands: plan.bands.len() as u32,
            node_bytes: plan.needed * NODE_BYTES,
        };
        self.drawn = true;
        let fill_group = self.lists.fill_group(device, &frame.targets.depth_view);
        let resolve_group = self
            .lists
            .resolve_group(device, &[self.uniforms.as_entire_binding()]);
        let [heads, nodes, counters] = self.lists.fill_buffers();
        for &band in &plan.bands {
            self.lists.begin_band(&mut frame.encoder);
            if strands {
                self.lists
                    .fill(frame, &FILL, &fill_group, band, "fur: explicit fill");
            }
            if let Some(shell) = shell {
                let timestamps = frame
                    .timer
                    .as_mut()
                    .and_then(|t| t.pass(crate::gpu::timing::Phase::FurShell, "fur: shell fill"));
                shell.record_fill(
                    gpu,
                    &mut frame.encoder,
                    frame.frame_bind_group,
                    heads,
                    nodes,
                    counters,
                    &frame.targets.depth_view,
                    &frame.targets.null_view,
                    timestamps,
                    Some(band),
                );
            }
            self.lists.resolve(frame, &resolve_group, band, "fur: resolve");
        }
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        self.lists.memory_bytes() + self.uniforms.size()
    }

    fn geometry_passes(&self) -> u32 {
        self.lists.geometry_passes()
    }

    fn depth_complexity(&self) -> Option<(u32, u64)> {
        Some((self.stats.deepest, self.stats.explicit + self.stats.shell))
    }

    fn fur(&self) -> Option<FurState<'_>> {
        self.fur.shell.as_ref().map(|s| FurState {
            shell: &s.gpu,
            lists: self.drawn.then_some(self as &dyn FurLists),
            volume_ms: s.volume_ms,
        })
    }
}
