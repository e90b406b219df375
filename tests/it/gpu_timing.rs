//! Per-pass GPU timing attributes a compute pass's work to that pass (`gpu::timing`): lavapipe takes a
//! timestamp's value at its next flush once a render pass has bound a framebuffer, and a compute pass's own
//! beginning timestamp then read the clock after its dispatch had run (timed 0.0 ms for a 420 ms dispatch).
//! The assertion is on where the time goes, not on how long it is: the spin pass must hold most of the
//! submission's wall-clock time.

use hairlab::gpu::Gpu;
use hairlab::gpu::timing::{GpuTimer, Phase};
use std::time::Instant;

const SPIN: &str = "@group(0) @binding(0) var<storage, read_write> out: array<f32>;
@compute @workgroup_size(64)
fn spin(@builtin(global_invocation_id) id: vec3<u32>) {
    var x = f32(id.x);
    for (var i = 0u; i < 1500u; i += 1u) {
        x = sin(x) + 1.0;
    }
    out[id.x] = x;
}";

#[test]
fn a_compute_pass_after_a_render_pass_is_timed_with_its_work() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let device = &gpu.device;
    let mut timer = GpuTimer::new(device, &gpu.queue).expect(
        "the adapter has no timestamp queries (lavapipe has them; this test needs them to check the timer)",
    );
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("spin"),
        source: wgpu::ShaderSource::Wgsl(SPIN.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("spin"),
        layout: None,
        module: &module,
        entry_point: Some("spin"),
        compilation_options: Default::default(),
        cache: None,
    });
    let groups = 1024;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("spin.out"),
        size: groups * 64 * 4,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("spin"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: out.as_entire_binding(),
        }],
    });
    let target = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("target"),
        size: wgpu::Extent3d {
            width: 64,
            height: 64,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    let view = target.create_view(&Default::default());
    // Twice: the first submission also compiles the pipeline on lavapipe.
    for round in 0..2 {
        let mut encoder = device.create_command_encoder(&Default::default());
        let render = timer.pass(Phase::Method, "clear");
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("clear"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &view,
                resolve_target: None,
                depth_slice: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: render,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let timestamps = timer.compute_pass(&mut encoder, Phase::Method, "spin");
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("spin"),
                timestamp_writes: timestamps,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(groups as u32, 1, 1);
        }
        assert!(timer.resolve(&mut encoder));
        let start = Instant::now();
        gpu.queue.submit([encoder.finish()]);
        timer.after_submit();
        let times = timer.wait(device).to_vec();
        let wall_ms = start.elapsed().as_secs_f64() * 1e3;
        let spin = times
            .iter()
            .find(|t| t.name == "spin")
            .expect("the spin pass's time");
        eprintln!(
            "round {round}: spin pass timed {:.1} ms of a {wall_ms:.1} ms submission",
            spin.ms
        );
        if round == 1 {
            assert!(
                spin.ms >= 0.5 * wall_ms,
                "the spin pass timed {:.1} ms of a {wall_ms:.1} ms submission: its work fell outside its timestamps",
                spin.ms
            );
        }
    }
}
