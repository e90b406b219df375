//! The shell pass of hybrid fur (Andersen, Falster, Frisvad, Christensen 2016, "Hybrid fur rendering: combining
//! volumetric fur with explicit hair strands", The Visual Computer, §3.2; spec B.5, B.8 step 4): the shell's
//! entry triangles ([`march::entry_triangles`]: front-facing tops and outward boundary walls, B.3 #6) are
//! rasterised, back faces culled, and every fragment the meshes do not hide runs `shaders/fur/shell.wgsl`'s port
//! of [`march::march`] along its pixel-centre ray ([`pixel_ray`]) from the Möller–Trumbore entry `t0` on its
//! triangle. The march runs twice: [`ShellGpu::record_count`] adds the fragments each pixel would get to the
//! counts (and the total) and the march statistics to the stats buffer; [`ShellGpu::record_fill`] appends
//! them to the eye lists as `EyeNode`s (`depth = t / camera_distance`, non-premultiplied colour, alpha,
//! `segment` = the entry prism, kind 1 SHELL or 2 VIRTUAL). The volume is stored (16 B per sub-element, `(τ, ρ)`),
//! computed on the GPU by [`density::compute_volume`] (its specification [`Volume::store`]); one over the
//! device's storage binding limit is an error.
//!
//! GPU = CPU (tests/it/fur_gpu.rs, lavapipe): t within 6e-8 world units, alpha 8e-7, colour 7.4e-5 on
//! `fur-cylinder`, but for the few pixels whose march passes within rounding of a sub-element boundary.
//!
//! Memory (Table 1 rows 1–2): 128 B per face and 8 B per entry triangle (the mesh data), 16 B per sub-element
//! (the volume densities).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3};

use crate::fur::march::{self, Emit, EntryTriangle, MarchParams, MarchStats};
use crate::fur::shell::Shell;
use crate::fur::volume::Volume;
use crate::gpu::readback::copy_out;
use crate::gpu::{Gpu, GpuError};
use crate::render::targets::EyeTargets;

use super::density;

/// The shell pass's WGSL.
pub const SHELL_WGSL: &str = "fur/shell.wgsl";
/// EyeNode kinds of the shell pass's fragments (B.7).
pub const KIND_SHELL: u32 = 1;
pub const KIND_VIRTUAL: u32 = 2;
/// 64-bit counters of the stats buffer, in [`MarchStats`] order: rays, steps, hops, light steps, lost, capped,
/// light lost.
const STATS: usize = 7;

/// The march parameters, mirrored field for field by `FurShellUniforms` in `shaders/fur/shell.wgsl` (a test
/// compares the layouts).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct FurShellUniforms {
    pub to_light: [f32; 3],
    pub sigma: f32,
    pub light: [f32; 3],
    pub step: f32,
    pub colour: [f32; 3],
    pub light_step: f32,
    pub max_steps: u32,
    pub hops: u32,
    pub epsilon_t: f32,
    pub light_steps: u32,
    /// Steps per emitted fragment: `k`, or `u32::MAX` for one shell fragment.
    pub group: u32,
    /// [`KIND_SHELL`] or [`KIND_VIRTUAL`].
    pub kind: u32,
    pub layers: u32,
    pub pad0: u32,
}

impl FurShellUniforms {
    /// `p` for a shell of `layers` layers. A group size of 0 (refused by [`MarchParams::validate`]) is taken as
    /// 1, so that the shader's group loop always advances.
    pub fn new(p: &MarchParams, layers: u32) -> FurShellUniforms {
        let (group, kind) = match p.emit {
            Emit::Shell => (u32::MAX, KIND_SHELL),
            Emit::Virtual(k) => (k.max(1), KIND_VIRTUAL),
        };
        FurShellUniforms {
            to_light: p.to_light.to_array(),
            sigma: p.sigma,
            light: p.light.to_array(),
            step: p.step,
            colour: p.colour.to_array(),
            light_step: p.light_step,
            max_steps: p.max_steps,
            hops: p.hops,
            epsilon_t: p.epsilon_t,
            light_steps: p.light_steps,
            group,
            kind,
            layers,
            pad0: 0,
        }
    }
}

/// Field names and byte offsets of [`FurShellUniforms`], in declaration order, for the layout test.
pub const FUR_SHELL_UNIFORMS_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("to_light", offset_of!(FurShellUniforms, to_light)),
        ("sigma", offset_of!(FurShellUniforms, sigma)),
        ("light", offset_of!(FurShellUniforms, light)),
        ("step", offset_of!(FurShellUniforms, step)),
        ("colour", offset_of!(FurShellUniforms, colour)),
        ("light_step", offset_of!(FurShellUniforms, light_step)),
        ("max_steps", offset_of!(FurShellUniforms, max_steps)),
        ("hops", offset_of!(FurShellUniforms, hops)),
        ("epsilon_t", offset_of!(FurShellUniforms, epsilon_t)),
        ("light_steps", offset_of!(FurShellUniforms, light_steps)),
        ("group", offset_of!(FurShellUniforms, group)),
        ("kind", offset_of!(FurShellUniforms, kind)),
        ("layers", offset_of!(FurShellUniforms, layers)),
        ("pad0", offset_of!(FurShellUniforms, pad0)),
    ]
};

/// One prism, mirrored by `FurFace` in `shaders/fur/shell.wgsl`: base and top corners (w unused), the faces
/// across its edges ([`crate::fur::mesh::NONE`]: none), its level and first global sub-element index.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct FurFace {
    pub base: [[f32; 4]; 3],
    pub top: [[f32; 4]; 3],
    pub neighbours: [u32; 3],
    pub level: u32,
    pub offset: u32,
    pub pad: [u32; 3],
}

/// Field names and byte offsets of [`FurFace`], for the layout test.
pub const FUR_FACE_FIELDS: &[(&str, usize)] = {
    use std::mem::offset_of;
    &[
        ("base", offset_of!(FurFace, base)),
        ("top", offset_of!(FurFace, top)),
        ("neighbours", offset_of!(FurFace, neighbours)),
        ("level", offset_of!(FurFace, level)),
        ("offset", offset_of!(FurFace, offset)),
        ("pad", offset_of!(FurFace, pad)),
    ]
};

/// The prisms of `shell` as uploaded. Offsets fit `u32`: [`Shell::build`] refuses more sub-elements.
pub fn faces(shell: &Shell) -> Vec<FurFace> {
    (0..shell.mesh.faces.len())
        .map(|f| {
            let (b, t) = shell.prism(f);
            FurFace {
                base: b.map(|v| v.extend(0.0).to_array()),
                top: t.map(|v| v.extend(0.0).to_array()),
                neighbours: shell.mesh.neighbours[f],
                level: shell.levels[f],
                offset: shell.offsets[f] as u32,
                pad: [0; 3],
            }
        })
        .collect()
}

/// The entry triangles as uploaded, `[face, which]` with `which` 0 for the top and `1 + 2e + s` for half `s`
/// of the wall on edge `e`, in [`march::entry_triangles`]' order.
pub fn entry_triangles(shell: &Shell) -> Vec<[u32; 2]> {
    march::entry_triangles(shell)
        .into_iter()
        .map(|(f, which)| match which {
            EntryTriangle::Top => [f, 0],
            EntryTriangle::Wall { edge, half } => [f, 1 + 2 * edge as u32 + half as u32],
        })
        .collect()
}

/// The unit eye ray through the centre of `pixel` of a `viewport` (width, height) under `world_to_clip`, as the
/// shader computes it ([`ray_through`] the centre `pixel + ½`).
pub fn pixel_ray(world_to_clip: &Mat4, viewport: [f32; 2], pixel: (u32, u32)) -> Vec3 {
    ray_through(
        world_to_clip,
        viewport,
        Vec2::new(pixel.0 as f32 + 0.5, pixel.1 as f32 + 0.5),
    )
}

/// The unit eye ray through framebuffer position `xy` (pixels, y down): the direction whose clip `x/w` and
/// `y/w` are the position's NDC, the cross product of the two clip-space planes through the eye (no matrix
/// inverse), turned to positive `w`.
pub fn ray_through(world_to_clip: &Mat4, viewport: [f32; 2], xy: Vec2) -> Vec3 {
    let ndc_x = xy.x / viewport[0] * 2.0 - 1.0;
    let ndc_y = 1.0 - xy.y / viewport[1] * 2.0;
    let m = world_to_clip;
    let row_x = Vec3::new(m.x_axis.x, m.y_axis.x, m.z_axis.x);
    let row_y = Vec3::new(m.x_axis.y, m.y_axis.y, m.z_axis.y);
    let row_w = Vec3::new(m.x_axis.w, m.y_axis.w, m.z_axis.w);
    let mut d = (row_x - ndc_x * row_w).cross(row_y - ndc_y * row_w);
    if row_w.dot(d) < 0.0 {
        d = -d;
    }
    d.normalize()
}

/// A storage binding: read-only ones are seen by both stages (the vertex stage pulls the entry triangles),
/// writable ones by the fragment stage only.
fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: if read_only {
            wgpu::ShaderStages::VERTEX_FRAGMENT
        } else {
            wgpu::ShaderStages::FRAGMENT
        },
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

const MESH_DEPTH_BINDING: u32 = 4;

fn mesh_depth_entry() -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: MESH_DEPTH_BINDING,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn buffer(device: &wgpu::Device, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: usage | wgpu::BufferUsages::COPY_DST,
    })
}

/// The shell pass: the uploaded shell and volume, its uniforms and statistics, and its two pipelines.
pub struct ShellGpu {
    params: wgpu::Buffer,
    faces: wgpu::Buffer,
    triangles: wgpu::Buffer,
    volume: wgpu::Buffer,
    stats: wgpu::Buffer,
    data_group: wgpu::BindGroup,
    count_layout: wgpu::BindGroupLayout,
    fill_layout: wgpu::BindGroupLayout,
    count_pipeline: wgpu::RenderPipeline,
    fill_pipeline: wgpu::RenderPipeline,
    triangle_count: u32,
    layers: u32,
    volume_ms: f64,
}

impl ShellGpu {
    /// Uploads the shell (per-face corners, neighbours, levels, offsets, entry triangles) and computes the stored
    /// volume on the GPU ([`density::compute_volume`] = [`Volume::store`], 16 B per sub-element), waiting for it
    /// ([`ShellGpu::volume_ms`]); a volume over the device's storage binding limit is an error naming the mesh,
    /// the sub-element count and the limit (checked before anything is uploaded).
    /// The march parameters start as [`MarchParams::for_shell`].
    pub fn new(
        gpu: &Gpu,
        frame_layout: &wgpu::BindGroupLayout,
        shell: &Shell,
        volume: &Volume,
    ) -> Result<ShellGpu, GpuError> {
        let device = &gpu.device;
        density::check_volume_fits(gpu, shell)?;
        let limits = device.limits();
        let limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let faces = faces(shell);
        let triangles = entry_triangles(shell);
        for (what, bytes) in [
            ("faces", std::mem::size_of_val(faces.as_slice())),
            ("entry triangles", std::mem::size_of_val(triangles.as_slice())),
        ] {
            if bytes as u64 > limit {
                return Err(GpuError::TooLarge {
                    what: format!("the fur shell {what} of mesh '{}'", shell.mesh.name),
                    bytes: bytes as u64,
                    limit,
                });
            }
        }
        let storage = wgpu::BufferUsages::STORAGE;
        let params = buffer(
            device,
            "hairlab.fur.shell.params",
            bytemuck::bytes_of(&FurShellUniforms::new(
                &MarchParams::for_shell(shell),
                shell.layers,
            )),
            wgpu::BufferUsages::UNIFORM,
        );
        let faces = buffer(
            device,
            "hairlab.fur.shell.faces",
            bytemuck::cast_slice(&faces),
            storage,
        );
        let triangle_count = triangles.len() as u32;
        let triangles = buffer(
            device,
            "hairlab.fur.shell.triangles",
            bytemuck::cast_slice(&triangles),
            storage,
        );
        let start = std::time::Instant::now();
        let volume = density::compute_volume(gpu, shell, &faces, &volume.params)?;
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Readback(format!("waiting for the fur volume pass: {e}")))?;
        let volume_ms = start.elapsed().as_secs_f64() * 1e3;
        let stats = buffer(
            device,
            "hairlab.fur.shell.stats",
            &[0; STATS * 8],
            storage | wgpu::BufferUsages::COPY_SRC,
        );
        let data_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.fur.shell.data_layout"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
                storage_entry(1, true),
                storage_entry(2, true),
                storage_entry(3, true),
                storage_entry(4, false),
            ],
        });
        let data_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.fur.shell.data_group"),
            layout: &data_layout,
            entries: &[&params, &faces, &triangles, &volume, &stats]
                .iter()
                .enumerate()
                .map(|(i, b)| wgpu::BindGroupEntry {
                    binding: i as u32,
                    resource: b.as_entire_binding(),
                })
                .collect::<Vec<_>>(),
        });
        let count_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.fur.shell.count_layout"),
            entries: &[storage_entry(0, false), mesh_depth_entry()],
        });
        let fill_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("hairlab.fur.shell.fill_layout"),
            entries: &[
                storage_entry(1, false),
                storage_entry(2, false),
                storage_entry(3, false),
                mesh_depth_entry(),
            ],
        });
        let module =
            crate::render::passes::shader_module(device, "hairlab.fur.shell.shader", SHELL_WGSL, None);
        let pipeline = |name: &str, lists: &wgpu::BindGroupLayout, entry: &str| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(&format!("hairlab.fur.shell.{name}_pipeline_layout")),
                bind_group_layouts: &[Some(frame_layout), Some(&data_layout), Some(lists)],
                immediate_size: 0,
            });
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&format!("hairlab.fur.shell.{name}_pipeline")),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode: Some(wgpu::Face::Back),
                    ..Default::default()
                },
                // The meshes are tested by hand (`common/mesh_depth.wgsl`), before the passes' side effects.
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &[Some(EyeTargets::NULL)],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let count_pipeline = pipeline("count", &count_layout, "fs_count");
        let fill_pipeline = pipeline("fill", &fill_layout, "fs_fill");
        Ok(ShellGpu {
            params,
            faces,
            triangles,
            volume,
            stats,
            data_group,
            count_layout,
            fill_layout,
            count_pipeline,
            fill_pipeline,
            triangle_count,
            layers: shell.layers,
            volume_ms,
        })
    }

    /// The march parameters of the next passes (to_light and the light's radiance are MarchParams'; the caller
    /// fills them from the scene's light). `p` is expected to pass [`MarchParams::validate`].
    pub fn set_params(&self, queue: &wgpu::Queue, p: &MarchParams) {
        queue.write_buffer(
            &self.params,
            0,
            bytemuck::bytes_of(&FurShellUniforms::new(p, self.layers)),
        );
    }

    /// The count pass: per pixel the number of fragments its shell fragments emit, added to `counts[pixel]` and
    /// `counts[W·H]` (clear `counts` first), and the march statistics added to the stats buffer
    /// ([`ShellGpu::reset_stats`]). `null_view` is the viewport-sized [`EyeTargets::NULL`] target, `rows` a band
    /// `[y0, y1)` (scissor).
    pub fn record_count(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        counts: &wgpu::Buffer,
        mesh_depth: &wgpu::TextureView,
        null_view: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
        rows: Option<(u32, u32)>,
    ) {
        let group = self.lists_group(gpu, "count", &self.count_layout, &[(0, counts)], mesh_depth);
        self.draw(
            encoder,
            "count",
            &self.count_pipeline,
            frame,
            &group,
            null_view,
            timestamps,
            rows,
        );
    }

    /// The fill pass: every emitted fragment appended to its pixel's list (`heads`, `nodes`, `counters[0]`
    /// nodes used, `counters[1]` fragments that did not fit; clear heads and counters first).
    pub fn record_fill(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        heads: &wgpu::Buffer,
        nodes: &wgpu::Buffer,
        counters: &wgpu::Buffer,
        mesh_depth: &wgpu::TextureView,
        null_view: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
        rows: Option<(u32, u32)>,
    ) {
        let group = self.lists_group(
            gpu,
            "fill",
            &self.fill_layout,
            &[(1, heads), (2, nodes), (3, counters)],
            mesh_depth,
        );
        self.draw(
            encoder,
            "fill",
            &self.fill_pipeline,
            frame,
            &group,
            null_view,
            timestamps,
            rows,
        );
    }

    fn lists_group(
        &self,
        gpu: &Gpu,
        name: &str,
        layout: &wgpu::BindGroupLayout,
        buffers: &[(u32, &wgpu::Buffer)],
        mesh_depth: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        let mut entries: Vec<_> = buffers
            .iter()
            .map(|(binding, b)| wgpu::BindGroupEntry {
                binding: *binding,
                resource: b.as_entire_binding(),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: MESH_DEPTH_BINDING,
            resource: wgpu::BindingResource::TextureView(mesh_depth),
        });
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(&format!("hairlab.fur.shell.{name}_group")),
            layout,
            entries: &entries,
        })
    }

    fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        name: &str,
        pipeline: &wgpu::RenderPipeline,
        frame: &wgpu::BindGroup,
        lists: &wgpu::BindGroup,
        null_view: &wgpu::TextureView,
        timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
        rows: Option<(u32, u32)>,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(&format!("hairlab.fur.shell.{name}_pass")),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: null_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: timestamps,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some((y0, y1)) = rows {
            if y1 <= y0 {
                return;
            }
            let width = null_view.texture().width();
            pass.set_scissor_rect(0, y0, width, y1 - y0);
        }
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, frame, &[]);
        pass.set_bind_group(1, &self.data_group, &[]);
        pass.set_bind_group(2, lists, &[]);
        pass.draw(0..3 * self.triangle_count, 0..1);
    }

    /// Zeroes the statistics (once per frame, before the count pass).
    pub fn reset_stats(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.stats, 0, None);
    }

    /// The statistics the count passes since the last [`ShellGpu::reset_stats`] added up (blocking readback).
    pub fn read_stats(&self, gpu: &Gpu) -> Result<MarchStats, GpuError> {
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&copy_out(gpu, &self.stats)?);
        let c = |k: usize| u64::from(words[2 * k]) | (u64::from(words[2 * k + 1]) << 32);
        Ok(MarchStats {
            rays: c(0),
            steps: c(1),
            hops: c(2),
            light_steps: c(3),
            lost: c(4),
            capped: c(5),
            light_lost: c(6),
        })
    }

    /// Wall time of the volume pass in [`ShellGpu::new`], submission to completion (ms).
    pub fn volume_ms(&self) -> f64 {
        self.volume_ms
    }

    /// The stored volume, `(τ.xyz, ρ)` per sub-element in global-index order.
    pub fn volume(&self) -> &wgpu::Buffer {
        &self.volume
    }

    /// Bytes by Table 1 row: (mesh data: faces, entry triangles and the uniforms; volume densities).
    pub fn memory(&self) -> (u64, u64) {
        (
            self.faces.size() + self.triangles.size() + self.params.size(),
            self.volume.size(),
        )
    }
}
