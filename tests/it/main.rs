//! hairlab's integration tests, as one test crate (one link of wgpu and egui instead of one per file). Each
//! module is one concern: the CLI, the file formats, the shaders, the GPU = CPU comparisons of every method,
//! the renderer's images, the window, the bench and the papers' stability claims. GPU tests run on Mesa
//! lavapipe when there is no GPU; with no adapter they fail saying what to install, unless
//! `HAIRLAB_SKIP_GPU_TESTS=1` is set. Run one module with `cargo test --test it <module>::`.

mod common;

mod app_ui;
mod bench;
mod chiang_shading;
mod cli;
mod compute_raster;
mod coverage_alpha;
mod docs;
mod fibre_light;
mod fibre_slab;
mod fur_density;
mod fur_gpu;
mod fur_guard;
mod fur_hybrid;
mod fur_march;
mod fur_shell;
mod fur_typed;
mod fuzz;
mod generate;
mod gltf_load;
mod gpu_avsm;
mod gpu_bom;
mod gpu_dc;
mod gpu_dom;
mod gpu_dsm;
mod gpu_fom;
mod gpu_msm;
mod gpu_occupancy;
mod gpu_opacity_layers;
mod gpu_render;
mod gpu_timing;
mod groom_formats;
mod hair_format;
mod inspector_ui;
mod light_ribbons;
mod light_supersample;
mod live_shaders;
mod measure_motion;
mod methods_gpu;
mod motion;
mod motion_claims;
mod motion_colliders;

mod path_render;
mod path_view;
mod pathtrace_numerics;
mod presets;
mod progress;
mod reference;
mod report;
mod ribbons;
mod scene_gpu;
mod shaders;
mod shading;
mod stability;
mod stability_avsm;
mod stability_dsm;
mod stability_fom;
mod stability_msm;
mod traced_probe;
mod transparency_claims;
mod transparency_gpu;
mod transparency_occupancy;
mod truth_decomposition;
#[cfg(feature = "usd")]
mod usd_composition;
mod usd_format;
mod visibility_models;
