//! Density Clustering (Mertens, Kautz, Bekaert & Van Reeth, EGSR 2004, §3.2-3.3): the fragments of a texel are
//! clustered in depth by one k-means iteration from `K` centres spread between the nearest and furthest
//! fragment; each cluster becomes a histogram bin `mu_j -+ sqrt(3) sigma_j` of uniform density, so the optical
//! depth is piecewise linear. `K` in 1..=16 (the paper uses 4). The CPU model is `visibility::dc`.
//!
//! GPU: two RGBA32F array textures of `2 ceil(K / 4)` layers each (clusters `4g..4g+3` in group `g`'s RGBA):
//! `hairlab.dc.clusters` holds the means (layer `2g`) and half-widths `D_j` (layer `2g + 1`);
//! `hairlab.dc.accum` is the additive target of the three geometry passes (layer `2g` sum of `b`, layer
//! `2g + 1` the weighted sum) and finally holds the densities (layer `2g`). Per frame: pass 1 (sum `b`, `b z`
//! by initial centre) → compute: means; pass 2 (sum `b`, `b (mu - z)^2` by nearest mean) → compute:
//! half-widths; pass 3 (histogram: sum `b` per bin). Three geometry passes for any `K`; at most 8 targets.

use super::{
    LightMethod, MethodContext, MethodGpu, MethodInfo, ParamKind, ParamSpec, ParamValues, Role, ShadowMethod,
    SweepPoint, UniformMirror, value,
};
use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError};
use crate::render::caster::{LightStage, draw_casters};
use crate::render::maps::{check_budget, cleared_attachments, texture_entry, uniform_entry};
use crate::visibility::dc::MAX_CLUSTERS;
use crate::visibility::{DcParams, TexelModel};
use bytemuck::{Pod, Zeroable};

/// Bytes of one RGBA32F texel.
const TEXEL_BYTES: u64 = 16;

const PARAMS: &[ParamSpec] = &[ParamSpec {
    key: "clusters",
    label: "clusters",
    help: "k-means depth clusters per texel, K (1..=16; the paper uses 4)",
    kind: ParamKind::Int {
        min: 1,
        max: MAX_CLUSTERS as i32,
    },
    default: 4.0,
}];

pub struct Dc;

fn clusters(values: &ParamValues) -> u32 {
    (value(values, &PARAMS[0]) as u32).clamp(1, MAX_CLUSTERS)
}

static INFO: MethodInfo = MethodInfo {
    name: "dc",
    label: "Density clustering",
    paper: "Mertens, Kautz, Bekaert & Van Reeth 2004 (§3.2-3.3)",
    role: Role::Approximation,
    lookup_wgsl: "methods/dc.wgsl",
    light_wgsl: &["dc.wgsl"],
    params: PARAMS,
    color: [214, 39, 40],
    gpu_tolerance: 1e-3,
    // The model is discontinuous in the last bits of its inputs (cluster and bin decisions): measured 271, 377
    // and 533 of 25,810 samples (1.0, 1.5, 2.1 %) beyond 1e-3 at K = 2, 4, 8 on the 300-strand test scene;
    // `tests/gpu_dc.rs` classifies and bounds each of them.
    gpu_outliers: 0.03,
};

/// The bench's cluster counts.
const SWEEP_CLUSTERS: &[u32] = &[2, 4, 8];

impl LightMethod for Dc {
    fn info(&self) -> &'static MethodInfo {
        &INFO
    }
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        Some(crate::uniform_mirror!(
            "DcUniforms",
            DcUniforms {
                clusters,
                pad0,
                pad1,
                pad2
            }
        ))
    }
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError> {
        Ok(Box::new(DcGpu::create(ctx)?))
    }
}

impl ShadowMethod for Dc {
    fn model(&self, values: &ParamValues, _hair_alpha: f32) -> Box<dyn TexelModel> {
        Box::new(DcParams {
            clusters: clusters(values),
        })
    }
    fn sweep(&self) -> Vec<SweepPoint> {
        SWEEP_CLUSTERS
            .iter()
            .map(|&n| SweepPoint::fixed(&[("clusters", n as f32)]))
            .collect()
    }
    fn scaling_configs(&self) -> Vec<ParamValues> {
        self.usual_configs()
    }
    fn usual_configs(&self) -> Vec<ParamValues> {
        vec![ParamValues::from([("clusters".to_string(), 4.0)])]
    }
}

/// Mirrors `DcUniforms` in `shaders/common/dc_uniforms.wgsl` (included by the lookup, which the light passes include).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct DcUniforms {
    pub clusters: u32,
    pub pad0: u32,
    pub pad1: u32,
    pub pad2: u32,
}

/// The three geometry passes' pipelines for one number of cluster groups.
struct DcPipelines {
    kmeans: wgpu::RenderPipeline,
    variance: wgpu::RenderPipeline,
    histogram: wgpu::RenderPipeline,
}

/// What does not depend on the parameters: layouts, pipelines, the uniform buffer.
struct DcResources {
    module: wgpu::ShaderModule,
    light: LightStage,
    depth_layout: wgpu::BindGroupLayout,
    clusters_layout: wgpu::BindGroupLayout,
    compute_layout: wgpu::BindGroupLayout,
    lookup_layout: wgpu::BindGroupLayout,
    means: wgpu::ComputePipeline,
    half_widths: wgpu::ComputePipeline,
    /// Render pipelines by number of groups `ceil(K / 4)` (1..=4), built on first use.
    pipelines: Vec<Option<DcPipelines>>,
    uniforms: wgpu::Buffer,
}

/// Density Clustering's GPU state, created with its maps (so they always exist).
pub struct DcGpu {
    res: DcResources,
    maps: DcMaps,
}

struct DcMaps {
    accum: wgpu::Texture,
    accum_layers: Vec<wgpu::TextureView>,
    clusters: wgpu::Texture,
    /// The light-depth map the bind groups read (re-created with the resolution).
    near: wgpu::Texture,
    groups: u32,
    /// Pass 1: near, far.
    depth_bind_group: wgpu::BindGroup,
    /// Passes 2 and 3: the clusters.
    clusters_bind_group: wgpu::BindGroup,
    /// Compute steps: accum, near, far, clusters (storage).
    compute_bind_group: wgpu::BindGroup,
    lookup_bind_group: wgpu::BindGroup,
}

/// Binding of DC's uniform in every group that has it.
const UNIFORM_BINDING: u32 = 2;

fn view_entry(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    }
}

impl DcResources {
    fn new(gpu: &Gpu, light: &LightStage) -> DcResources {
        use wgpu::ShaderStages as S;
        use wgpu::TextureViewDimension::{D2, D2Array};
        let device = &gpu.device;
        // Binding numbers are those of shaders/methods/dc.wgsl and shaders/dc.wgsl: 0 clusters, 1 accum,
        // 2 uniforms, 3 near, 4 far, 5 clusters (storage).
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let depth_layout = layout(
            "hairlab.dc.depth_layout",
            &[
                uniform_entry(UNIFORM_BINDING, S::FRAGMENT),
                texture_entry(3, S::FRAGMENT, D2),
                texture_entry(4, S::FRAGMENT, D2),
            ],
        );
        let clusters_layout = layout(
            "hairlab.dc.clusters_layout",
            &[
                texture_entry(0, S::FRAGMENT, D2Array),
                uniform_entry(UNIFORM_BINDING, S::FRAGMENT),
            ],
        );
        let compute_layout = layout(
            "hairlab.dc.compute_layout",
            &[
                texture_entry(1, S::COMPUTE, D2Array),
                uniform_entry(UNIFORM_BINDING, S::COMPUTE),
                texture_entry(3, S::COMPUTE, D2),
                texture_entry(4, S::COMPUTE, D2),
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: S::COMPUTE,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: wgpu::TextureFormat::Rgba32Float,
                        view_dimension: D2Array,
                    },
                    count: None,
                },
            ],
        );
        let look = S::FRAGMENT | S::COMPUTE;
        let lookup_layout = layout(
            "hairlab.dc.lookup_layout",
            &[
                texture_entry(0, look, D2Array),
                texture_entry(1, look, D2Array),
                uniform_entry(UNIFORM_BINDING, look),
            ],
        );
        let module = light.module(device, "hairlab.dc.shader", "dc.wgsl");
        // The compute steps use group 1 only (group 0 is the light passes' frame uniforms).
        let compute_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("hairlab.dc.compute_pipeline_layout"),
            bind_group_layouts: &[None, Some(&compute_layout)],
            immediate_size: 0,
        });
        let compute = |label, entry| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&compute_pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let means = compute("hairlab.dc.means_pipeline", "cs_means");
        let half_widths = compute("hairlab.dc.half_widths_pipeline", "cs_half_widths");
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.dc.uniforms"),
            size: std::mem::size_of::<DcUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        DcResources {
            module,
            light: light.clone(),
            depth_layout,
            clusters_layout,
            compute_layout,
            lookup_layout,
            means,
            half_widths,
            pipelines: (0..MAX_CLUSTERS / 4).map(|_| None).collect(),
            uniforms,
        }
    }

    /// The maps for `groups` cluster groups at `ctx`'s resolution, within hairlab's map budget.
    fn make_maps(&self, ctx: &MethodContext, groups: u32) -> Result<DcMaps, GpuError> {
        let resolution = ctx.map_resolution();
        let near = &ctx.light_maps.near;
        check_budget(
            || {
                format!(
                    "density clustering maps of {} RGBA32F layers at {resolution}²",
                    4 * groups
                )
            },
            map_bytes(resolution, groups),
        )?;
        let device = &ctx.gpu.device;
        let texture = |label, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: resolution,
                    height: resolution,
                    depth_or_array_layers: 2 * groups,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba32Float,
                usage: usage | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
        };
        let accum = texture("hairlab.dc.accum", wgpu::TextureUsages::RENDER_ATTACHMENT);
        let clusters = texture("hairlab.dc.clusters", wgpu::TextureUsages::STORAGE_BINDING);
        let accum_layers = (0..2 * groups)
            .map(|l| {
                accum.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("hairlab.dc.accum_layer"),
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: l,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        let array_view = |t: &wgpu::Texture, label| {
            t.create_view(&wgpu::TextureViewDescriptor {
                label: Some(label),
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        let accum_view = array_view(&accum, "hairlab.dc.accum_view");
        let clusters_view = array_view(&clusters, "hairlab.dc.clusters_view");
        let uniforms = wgpu::BindGroupEntry {
            binding: 2,
            resource: self.uniforms.as_entire_binding(),
        };
        let (near_view, far_view) = (&ctx.light_maps.near_view, &ctx.light_maps.far_view);
        let bind_group = |label, layout, entries: &[wgpu::BindGroupEntry]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries,
            })
        };
        let depth_bind_group = bind_group(
            "hairlab.dc.depth_bind_group",
            &self.depth_layout,
            &[
                uniforms.clone(),
                view_entry(3, near_view),
                view_entry(4, far_view),
            ],
        );
        let clusters_bind_group = bind_group(
            "hairlab.dc.clusters_bind_group",
            &self.clusters_layout,
            &[view_entry(0, &clusters_view), uniforms.clone()],
        );
        let compute_bind_group = bind_group(
            "hairlab.dc.compute_bind_group",
            &self.compute_layout,
            &[
                view_entry(1, &accum_view),
                uniforms.clone(),
                view_entry(3, near_view),
                view_entry(4, far_view),
                view_entry(5, &clusters_view),
            ],
        );
        let lookup_bind_group = bind_group(
            "hairlab.dc.lookup_bind_group",
            &self.lookup_layout,
            &[
                view_entry(0, &clusters_view),
                view_entry(1, &accum_view),
                uniforms,
            ],
        );
        Ok(DcMaps {
            accum,
            accum_layers,
            clusters,
            near: near.clone(),
            groups,
            depth_bind_group,
            clusters_bind_group,
            compute_bind_group,
            lookup_bind_group,
        })
    }

    fn pipelines(&mut self, device: &wgpu::Device, frame_layout: &wgpu::BindGroupLayout, groups: u32) {
        let slot = &mut self.pipelines[groups as usize - 1];
        if slot.is_some() {
            return;
        }
        let depth = [frame_layout, &self.depth_layout];
        let clusters = [frame_layout, &self.clusters_layout];
        let add = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let state = Some(wgpu::ColorTargetState {
            format: wgpu::TextureFormat::Rgba32Float,
            blend: Some(wgpu::BlendState {
                color: add,
                alpha: add,
            }),
            write_mask: wgpu::ColorWrites::ALL,
        });
        let sums = vec![state.clone(); 2 * groups as usize];
        let densities = vec![state; groups as usize];
        let module = &self.module;
        *slot = Some(DcPipelines {
            kmeans: self.light.pipeline(
                device,
                "hairlab.dc.kmeans_pipeline",
                &depth,
                module,
                "fs_kmeans",
                &sums,
            ),
            variance: self.light.pipeline(
                device,
                "hairlab.dc.variance_pipeline",
                &clusters,
                module,
                "fs_variance",
                &sums,
            ),
            histogram: self.light.pipeline(
                device,
                "hairlab.dc.histogram_pipeline",
                &clusters,
                module,
                "fs_histogram",
                &densities,
            ),
        });
    }
}

/// Bytes of both textures: `2 * 2 * groups` RGBA32F layers.
fn map_bytes(resolution: u32, groups: u32) -> u64 {
    resolution as u64 * resolution as u64 * 4 * groups as u64 * TEXEL_BYTES
}

/// Clears `views` and draws the strands into them with `pipeline` and group 1 `resources`.
fn geometry_pass(
    ctx: &MethodContext,
    encoder: &mut wgpu::CommandEncoder,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
    views: &[&wgpu::TextureView],
    pipeline: &wgpu::RenderPipeline,
    resources: &wgpu::BindGroup,
) {
    let attachments = cleared_attachments(views);
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("hairlab.dc.pass"),
        color_attachments: &attachments,
        depth_stencil_attachment: None,
        timestamp_writes: timestamps,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    draw_casters(
        &mut pass,
        pipeline,
        ctx.frame_bind_group,
        Some(resources),
        ctx.casters,
        0..1,
    );
}

/// Runs `pipeline` once per texel.
fn compute_pass(
    encoder: &mut wgpu::CommandEncoder,
    timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    pipeline: &wgpu::ComputePipeline,
    resources: &wgpu::BindGroup,
    resolution: u32,
) {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("hairlab.dc.compute"),
        timestamp_writes: timestamps,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(1, resources, &[]);
    let groups = resolution.div_ceil(8);
    pass.dispatch_workgroups(groups, groups, 1);
}

impl DcGpu {
    fn create(ctx: &MethodContext) -> Result<DcGpu, GpuError> {
        let res = DcResources::new(ctx.gpu, ctx.light);
        let maps = res.make_maps(ctx, clusters(ctx.values).div_ceil(4))?;
        Ok(DcGpu { res, maps })
    }
}

impl MethodGpu for DcGpu {
    fn prepare(&mut self, ctx: &MethodContext, _timer: &mut Option<GpuTimer>) -> Result<(), GpuError> {
        let k = clusters(ctx.values);
        let groups = k.div_ceil(4);
        if self.maps.groups != groups || self.maps.near != ctx.light_maps.near {
            self.maps = self.res.make_maps(ctx, groups)?;
        }
        self.res.pipelines(&ctx.gpu.device, ctx.frame_layout, groups);
        ctx.gpu.queue.write_buffer(
            &self.res.uniforms,
            0,
            bytemuck::bytes_of(&DcUniforms {
                clusters: k,
                ..Zeroable::zeroed()
            }),
        );
        Ok(())
    }

    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) {
        let groups = self.maps.groups;
        let maps = &self.maps;
        let Some(pipelines) = self.res.pipelines[groups as usize - 1].as_ref() else {
            return;
        };
        let resolution = ctx.map_resolution();
        let sums: Vec<_> = maps.accum_layers.iter().collect();
        let densities: Vec<_> = maps.accum_layers.iter().step_by(2).collect();
        geometry_pass(
            ctx,
            encoder,
            timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::Method, "dc: k-means")),
            &sums,
            &pipelines.kmeans,
            &maps.depth_bind_group,
        );
        let timestamps = timer
            .as_mut()
            .and_then(|t| t.compute_pass(encoder, crate::gpu::timing::Phase::Method, "dc: means"));
        compute_pass(
            encoder,
            timestamps,
            &self.res.means,
            &maps.compute_bind_group,
            resolution,
        );
        geometry_pass(
            ctx,
            encoder,
            timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::Method, "dc: variance")),
            &sums,
            &pipelines.variance,
            &maps.clusters_bind_group,
        );
        let timestamps = timer
            .as_mut()
            .and_then(|t| t.compute_pass(encoder, crate::gpu::timing::Phase::Method, "dc: half-widths"));
        compute_pass(
            encoder,
            timestamps,
            &self.res.half_widths,
            &maps.compute_bind_group,
            resolution,
        );
        geometry_pass(
            ctx,
            encoder,
            timer
                .as_mut()
                .and_then(|t| t.pass(crate::gpu::timing::Phase::Method, "dc: histogram")),
            &densities,
            &pipelines.histogram,
            &maps.clusters_bind_group,
        );
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.res.lookup_layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.maps.lookup_bind_group
    }
    fn memory_bytes(&self) -> u64 {
        let texture_bytes = |t: &wgpu::Texture| {
            t.width() as u64 * t.height() as u64 * t.depth_or_array_layers() as u64 * TEXEL_BYTES
        };
        texture_bytes(&self.maps.accum) + texture_bytes(&self.maps.clusters)
    }
    fn geometry_passes(&self) -> u32 {
        3
    }
}
