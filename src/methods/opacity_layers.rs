//! The GPU side shared by every method that stores `K` values per texel in RGBA32F layers filled by additive
//! light passes: Opacity Shadow Maps (`K` slices over the whole light range), Deep Opacity Maps and Bounding
//! Opacity Maps (`K` layers placed per texel from the shared near/far maps), Fourier opacity maps (`2K + 1`
//! Fourier coefficients) and moment shadow maps (the power moments). Each keeps only its shader, its uniforms
//! and its setup; the map, the pipelines and the passes are here.
//!
//! Layout: an [`ArrayMap`] of `ceil(K / 4)` layers (4 values per RGBA texel), written by `ceil(layers / 8)`
//! geometry passes of at most 8 colour targets; pass `p` draws with instance index `p` so that the shader knows
//! which targets it writes. The light pass's group 1 is the uniform (binding 0) and the near (1) and far (2)
//! light-depth maps; the lookup's group 1 is the array view (0) and the uniform (1).

use super::{MethodContext, MethodGpu, ParamValues};
use crate::gpu::GpuError;
use crate::gpu::timing::GpuTimer;
use crate::render::caster::draw_casters;
use crate::render::maps::{
    AdditivePipelines, ArrayMap, LOOKUP_STAGES, texture_entry, uniform_buffer, uniform_entry,
};
use bytemuck::Pod;

/// Values one RGBA32F layer holds.
pub const VALUES_PER_LAYER: u32 = 4;

/// What tells one layered method's GPU side from another's.
pub struct LayerMethod<U> {
    /// Method name, for labels (`hairlab.<name>.<resource>`) and timings.
    pub name: &'static str,
    /// What a stored value is called in pass timings (`slices`, `layers`).
    pub unit: &'static str,
    /// The light-pass shader: `vs_main`, `fs_main` writing up to 8 RGBA32F outputs.
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
    /// Read by both the light pass and the lookup.
    pub uniforms: U,
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
}

/// GPU state of a layered method; created with its maps for the current parameters, so it always has them.
pub struct LayersGpu<U> {
    method: LayerMethod<U>,
    pass_layout: wgpu::BindGroupLayout,
    lookup_layout: wgpu::BindGroupLayout,
    pipelines: AdditivePipelines,
    uniforms: wgpu::Buffer,
    pass_bind_group: PassBindGroup,
    maps: Maps,
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
            module,
            "fs_main",
        );
        let setup = (method.setup)(ctx.values);
        let pass_bind_group = pass_bind_group(ctx, name, &pass_layout, &uniforms);
        let maps = make_maps(ctx, name, &lookup_layout, &uniforms, layers_for(setup.values))?;
        Ok(LayersGpu {
            method,
            pass_layout,
            lookup_layout,
            pipelines,
            uniforms,
            pass_bind_group,
            maps,
            setup,
        })
    }
}

/// Array layers holding `values` values.
fn layers_for(values: u32) -> u32 {
    values.max(1).div_ceil(VALUES_PER_LAYER)
}

fn make_maps(
    ctx: &MethodContext,
    name: &str,
    lookup_layout: &wgpu::BindGroupLayout,
    uniforms: &wgpu::Buffer,
    layers: u32,
) -> Result<Maps, GpuError> {
    let map = ArrayMap::new(ctx.gpu, &format!("{name}.layers"), ctx.map_resolution(), layers)?;
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
        if self.maps.map.resolution != ctx.map_resolution() || self.maps.map.layers != layers {
            self.maps = make_maps(ctx, name, &self.lookup_layout, &self.uniforms, layers)?;
        }
        let p = &self.pass_bind_group;
        if p.near != ctx.light_maps.near_view || p.far != ctx.light_maps.far_view {
            self.pass_bind_group = pass_bind_group(ctx, name, &self.pass_layout, &self.uniforms);
        }
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
                    crate::gpu::timing::Phase::Method,
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

    fn geometry_passes(&self) -> u32 {
        self.maps.map.layers.div_ceil(AdditivePipelines::MAX_TARGETS)
    }
}
