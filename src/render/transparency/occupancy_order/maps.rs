//! Passes 1 and 2 of occupancy-ordered blending: S&A's Occupancy Maps built from the camera, what the hair pass
//! (group 2) and the resolve read. Both passes run the shared eye vertex stage over the strands as lines.
//! 1. `eye: depth range`: the pixel's nearest and furthest eye depth, two [`RANGE`] targets cleared to
//!    (big, 0) with Min / Max blending, tested `Less` against the meshes' depth without writing (spec A.3 #7: the
//!    paper's two depth-test passes in one);
//! 2. `eye: occupancy + slabs`: the 128-slice occupancy bitmap and the 4 slab counts of the pixel, `atomicOr` /
//!    `atomicAdd` into two storage buffers of four u32 per pixel, the meshes tested by hand before the atomics.

use super::{BUFFER_BYTES_PER_PIXEL, INFO, RANGE};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::bindings::{self, Binding};
use crate::render::eye::passes::{self, LinePass};
use crate::render::eye::pipelines::{self, DepthTest, GeometryPass};
use crate::render::eye::targets::{self, Textures};
use crate::render::passes::shader_module;
use crate::render::targets::EyeTargets;
use crate::render::transparency::{EyeFrame, EyeSetup, HairGeometry};

/// The depth-range targets' clear value of `near` (beyond any eye depth; `far` clears to 0).
const NEAR_CLEAR: f64 = 1e30;

/// The maps' group: the two depth ranges, the bitmap, the slab counts and the uniforms; group 2 of the hair
/// pass (read-only), or group 1 of the occupancy pass (writable, and the meshes' depth it tests by hand).
fn maps_group(occupancy_pass: bool) -> &'static [Binding] {
    use Binding::{MeshDepth, StorageRo, StorageRw, Texture, Uniform};
    if occupancy_pass {
        &[Texture, Texture, StorageRw, StorageRw, Uniform, MeshDepth]
    } else {
        &[Texture, Texture, StorageRo, StorageRo, Uniform]
    }
}

/// A blend of the depth-range targets' red channel by `operation` (Min or Max).
const fn range_target(operation: wgpu::BlendOperation) -> Option<wgpu::ColorTargetState> {
    Some(wgpu::ColorTargetState {
        format: RANGE,
        blend: Some(wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation,
            },
            alpha: wgpu::BlendComponent::REPLACE,
        }),
        write_mask: wgpu::ColorWrites::RED,
    })
}

/// The occupancy bitmap and the slab counts for a `size` viewport; refused beyond the device's storage binding
/// size.
fn map_buffers(gpu: &Gpu, (width, height): (u32, u32)) -> Result<[wgpu::Buffer; 2], GpuError> {
    let what = format!(
        "occupancy-order's occupancy bitmap and slab map at the {width}×{height} viewport \
         ({BUFFER_BYTES_PER_PIXEL} bytes per pixel each; make the viewport smaller)"
    );
    let bytes = width as u64 * height as u64 * BUFFER_BYTES_PER_PIXEL;
    Ok([
        targets::storage(gpu, INFO.name, "bitmap", &what, bytes)?,
        targets::storage(gpu, INFO.name, "slabs", &what, bytes)?,
    ])
}

/// The maps of one viewport size and the two passes that build them.
pub(super) struct OccupancyMaps {
    range_pipeline: wgpu::RenderPipeline,
    slabs_pipeline: wgpu::RenderPipeline,
    pass_layout: wgpu::BindGroupLayout,
    /// Group 2 of the hair pass.
    pub hair_layout: wgpu::BindGroupLayout,
    /// The nearest and furthest eye depth.
    range: Textures,
    bits: wgpu::Buffer,
    pub slabs: wgpu::Buffer,
}

impl OccupancyMaps {
    pub fn new(setup: &EyeSetup) -> Result<OccupancyMaps, GpuError> {
        let device = &setup.gpu.device;
        let pass_layout = bindings::layout(device, "hairlab.occupancy-order.pass_layout", maps_group(true));
        let module = shader_module(
            device,
            "hairlab.occupancy-order.maps_shader",
            INFO.pass_wgsl[0],
            None,
        );
        let pass = |label, layouts, fragment, targets, depth| {
            pipelines::geometry(
                device,
                &GeometryPass {
                    label,
                    module: &module,
                    layouts,
                    geometry: HairGeometry::Lines,
                    fragment,
                    targets,
                    depth,
                },
            )
        };
        let size = (setup.width, setup.height);
        let [bits, slabs] = map_buffers(setup.gpu, size)?;
        Ok(OccupancyMaps {
            range_pipeline: pass(
                "hairlab.occupancy-order.range_pipeline",
                &[setup.frame_layout],
                "fs_range",
                &[
                    range_target(wgpu::BlendOperation::Min),
                    range_target(wgpu::BlendOperation::Max),
                ],
                Some(DepthTest::Meshes),
            ),
            slabs_pipeline: pass(
                "hairlab.occupancy-order.slabs_pipeline",
                &[setup.frame_layout, &pass_layout],
                "fs_slabs",
                &[Some(EyeTargets::NULL)],
                None,
            ),
            pass_layout,
            hair_layout: bindings::layout(device, "hairlab.occupancy-order.hair_layout", maps_group(false)),
            range: Textures::new(device, INFO.name, &[("near", RANGE), ("far", RANGE)], size),
            bits,
            slabs,
        })
    }

    pub fn resize(&mut self, gpu: &Gpu, size: (u32, u32)) -> Result<(), GpuError> {
        if self.range.size() != size {
            [self.bits, self.slabs] = map_buffers(gpu, size)?;
            self.range.resize(&gpu.device, size);
        }
        Ok(())
    }

    /// A group of [`maps_group`] over the maps and `uniforms`; for the occupancy pass with the meshes' depth.
    pub fn group(
        &self,
        device: &wgpu::Device,
        uniforms: &wgpu::Buffer,
        mesh_depth: Option<&wgpu::TextureView>,
    ) -> wgpu::BindGroup {
        let (label, layout) = match mesh_depth {
            Some(_) => ("hairlab.occupancy-order.pass_bind_group", &self.pass_layout),
            None => ("hairlab.occupancy-order.hair_bind_group", &self.hair_layout),
        };
        let mut resources = vec![
            wgpu::BindingResource::TextureView(self.range.view(0)),
            wgpu::BindingResource::TextureView(self.range.view(1)),
            self.bits.as_entire_binding(),
            self.slabs.as_entire_binding(),
            uniforms.as_entire_binding(),
        ];
        resources.extend(mesh_depth.map(wgpu::BindingResource::TextureView));
        bindings::group(device, label, layout, &resources)
    }

    /// Records passes 1 and 2, the occupancy pass reading `uniforms`.
    pub fn record(&self, frame: &mut EyeFrame<'_>, uniforms: &wgpu::Buffer) {
        passes::record_lines(
            frame,
            LinePass {
                label: "hairlab.occupancy-order.range_pass",
                timer: "eye: depth range",
                pipeline: &self.range_pipeline,
                group: None,
                attachments: &self.range.cleared(&[[NEAR_CLEAR, 0.0, 0.0, 0.0], [0.0; 4]]),
                mesh_depth: true,
            },
        );
        frame.encoder.clear_buffer(&self.bits, 0, None);
        frame.encoder.clear_buffer(&self.slabs, 0, None);
        // The meshes' depth is tested by hand before the atomics (a fixed-function test after the shader would
        // not undo them); the depth view is the frame's, so the group is too.
        let group = self.group(&frame.gpu.device, uniforms, Some(&frame.targets.depth_view));
        passes::record_line_count(
            frame,
            "hairlab.occupancy-order.slabs_pass",
            "eye: occupancy + slabs",
            &self.slabs_pipeline,
            &group,
        );
    }

    pub fn bytes(&self) -> u64 {
        self.range.bytes() + self.bits.size() + self.slabs.size()
    }
}
