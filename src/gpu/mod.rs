//! Device and adapter policy, buffer limits, per-pass GPU timing and readback.
//!
//! Policy: prefer a hardware adapter and fall back to a software one (Mesa lavapipe); tests and
//! `HAIRLAB_ADAPTER=software` prefer the software adapter. An adapter must support the features every pass needs.

pub mod readback;
pub mod timing;

use std::sync::Arc;

/// Features every hairlab pass needs: min/max blending of R32Float light-depth targets.
pub const REQUIRED_FEATURES: wgpu::Features = wgpu::Features::FLOAT32_BLENDABLE;
/// Features used when present: per-pass GPU timing.
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY;

/// Environment variable that lets a machine with no GPU adapter skip the GPU tests explicitly.
pub const SKIP_GPU_TESTS_ENV: &str = "HAIRLAB_SKIP_GPU_TESTS";

/// What to install when no adapter exists.
pub const INSTALL_HINT: &str =
    "install a Vulkan driver; on GPU-less Debian/Ubuntu: apt-get install mesa-vulkan-drivers";

#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("no GPU adapter found ({INSTALL_HINT})")]
    NoAdapter,
    #[error("no adapter supports {missing:?} (found: {found}); {INSTALL_HINT}")]
    MissingFeatures { missing: wgpu::Features, found: String },
    #[error("cannot open the GPU device on {adapter}: {cause}")]
    RequestDevice {
        adapter: String,
        cause: wgpu::RequestDeviceError,
    },
    #[error("{what} needs {bytes} bytes, more than this GPU allows in one buffer ({limit} bytes)")]
    TooLarge { what: String, bytes: u64, limit: u64 },
    #[error(
        "{what} needs {bytes} bytes, more than hairlab's light-map budget of {budget} bytes (a limit of this \
         workbench, not of the GPU)"
    )]
    OverBudget { what: String, bytes: u64, budget: u64 },
    #[error("GPU readback failed: {0}")]
    Readback(String),
    /// A render setting the renderer cannot follow; the message names the key.
    #[error("{0}")]
    Setting(String),
    /// Moved strand points whose count is not the scene's.
    #[error(transparent)]
    Points(#[from] crate::scene::PointCountMismatch),
}

/// Which kind of adapter to try first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdapterPreference {
    Hardware,
    Software,
}

impl AdapterPreference {
    /// `HAIRLAB_ADAPTER=software|hardware` overrides `default`.
    pub fn from_env_or(default: AdapterPreference) -> AdapterPreference {
        match std::env::var("HAIRLAB_ADAPTER").as_deref() {
            Ok("software") => AdapterPreference::Software,
            Ok("hardware") => AdapterPreference::Hardware,
            _ => default,
        }
    }
}

fn rank(info: &wgpu::AdapterInfo, pref: AdapterPreference) -> u32 {
    use wgpu::DeviceType::*;
    let hw = match info.device_type {
        DiscreteGpu => 0,
        IntegratedGpu => 1,
        VirtualGpu => 2,
        Other => 3,
        Cpu => 4,
    };
    match pref {
        AdapterPreference::Hardware => hw,
        AdapterPreference::Software => 4 - hw,
    }
}

/// Picks the adapter by policy among those with [`REQUIRED_FEATURES`].
pub fn select_adapter(
    adapters: &[wgpu::Adapter],
    pref: AdapterPreference,
) -> Result<wgpu::Adapter, GpuError> {
    if adapters.is_empty() {
        return Err(GpuError::NoAdapter);
    }
    adapters
        .iter()
        .filter(|a| a.features().contains(REQUIRED_FEATURES))
        .min_by_key(|a| rank(&a.get_info(), pref))
        .cloned()
        .ok_or_else(|| GpuError::MissingFeatures {
            missing: REQUIRED_FEATURES,
            found: adapters
                .iter()
                .map(|a| a.get_info().name)
                .collect::<Vec<_>>()
                .join(", "),
        })
}

/// The device request hairlab makes of an adapter: required + available optional features, the adapter's limits.
pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
    wgpu::DeviceDescriptor {
        label: Some("hairlab.device"),
        required_features: REQUIRED_FEATURES | (adapter.features() & OPTIONAL_FEATURES),
        required_limits: adapter.limits(),
        ..Default::default()
    }
}

/// One line describing an adapter for the UI and the log.
pub fn describe(info: &wgpu::AdapterInfo) -> String {
    let kind = if info.device_type == wgpu::DeviceType::Cpu {
        "software"
    } else {
        "hardware"
    };
    format!("{} ({kind}, {:?})", info.name, info.backend)
}

/// Backends hairlab enumerates (overridable with `WGPU_BACKEND`).
pub fn backends() -> wgpu::Backends {
    wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY)
}

/// A device with its queue and what hairlab knows about it.
#[derive(Clone)]
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
}

impl Gpu {
    /// Wraps a device created elsewhere (eframe's).
    pub fn from_parts(device: wgpu::Device, queue: wgpu::Queue, info: wgpu::AdapterInfo) -> Gpu {
        Gpu { device, queue, info }
    }

    /// Opens a device with no window, by the adapter policy.
    pub fn headless(pref: AdapterPreference) -> Result<Gpu, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends: backends(),
            ..wgpu::InstanceDescriptor::new_without_display_handle_from_env()
        });
        let adapters = pollster::block_on(instance.enumerate_adapters(backends()));
        let adapter = select_adapter(&adapters, pref)?;
        let info = adapter.get_info();
        let (device, queue) = pollster::block_on(adapter.request_device(&device_descriptor(&adapter)))
            .map_err(|cause| GpuError::RequestDevice {
                adapter: describe(&info),
                cause,
            })?;
        log::info!("GPU: {}", describe(&info));
        Ok(Gpu { device, queue, info })
    }

    /// The device for tests: prefers the software adapter. With no adapter it fails with what to install, unless
    /// `HAIRLAB_SKIP_GPU_TESTS=1` is set, in which case it returns `None` and says so on stderr.
    pub fn for_tests() -> Option<Gpu> {
        match Gpu::headless(AdapterPreference::from_env_or(AdapterPreference::Software)) {
            Ok(gpu) => Some(gpu),
            Err(e) if std::env::var(SKIP_GPU_TESTS_ENV).is_ok_and(|v| v == "1") => {
                eprintln!("GPU test skipped on request ({SKIP_GPU_TESTS_ENV}=1): {e}");
                None
            }
            Err(e) => {
                panic!("GPU tests need an adapter: {e}. Set {SKIP_GPU_TESTS_ENV}=1 to skip them explicitly.")
            }
        }
    }

    pub fn timestamps_supported(&self) -> bool {
        self.device.features().contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// Checks that a buffer of `bytes` fits this device's limits.
    pub fn check_buffer_size(&self, what: &str, bytes: u64) -> Result<(), GpuError> {
        let limits = self.device.limits();
        let limit = limits.max_buffer_size;
        if bytes > limit {
            return Err(GpuError::TooLarge {
                what: what.to_string(),
                bytes,
                limit,
            });
        }
        Ok(())
    }

    /// Checks that a square texture of side `size` fits the device.
    pub fn check_texture_size(&self, what: &str, size: u32) -> Result<(), GpuError> {
        let limit = self.device.limits().max_texture_dimension_2d;
        if size > limit {
            return Err(GpuError::TooLarge {
                what: format!("{what} ({size} texels wide)"),
                bytes: size as u64,
                limit: limit as u64,
            });
        }
        Ok(())
    }
}

/// The adapter selector handed to eframe: the same policy as [`Gpu::headless`].
pub fn eframe_adapter_selector() -> egui_wgpu::NativeAdapterSelectorMethod {
    Arc::new(|adapters, _surface| {
        select_adapter(
            adapters,
            AdapterPreference::from_env_or(AdapterPreference::Hardware),
        )
        .map_err(|e| e.to_string())
    })
}
