//! Device and adapter policy, buffer limits, per-pass GPU timing and readback.
//!
//! Policy: prefer a hardware adapter and fall back to a software one (Mesa lavapipe); tests and
//! `HAIRLAB_ADAPTER=software` prefer the software adapter. Any other `HAIRLAB_ADAPTER` value, or the command
//! line's `--adapter NAME` (which wins over the variable), chooses the adapter whose name contains it (any case).
//! An adapter must support the features every pass needs.

pub mod readback;
pub mod timing;

use std::sync::{Arc, OnceLock};

/// Features every hairlab pass needs: min/max blending of R32Float light-depth targets.
pub const REQUIRED_FEATURES: wgpu::Features = wgpu::Features::FLOAT32_BLENDABLE;
/// Features used when present: per-pass GPU timing.
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY;

/// Environment variable that chooses the adapter: `software`, `hardware`, or a part of its name.
pub const ADAPTER_ENV: &str = "HAIRLAB_ADAPTER";

/// Environment variable that lets a machine with no GPU adapter skip the GPU tests explicitly.
pub const SKIP_GPU_TESTS_ENV: &str = "HAIRLAB_SKIP_GPU_TESTS";

/// What to install when no adapter exists.
pub const INSTALL_HINT: &str =
    "install a Vulkan driver; on GPU-less Debian/Ubuntu: apt-get install mesa-vulkan-drivers";

#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("no GPU adapter found ({INSTALL_HINT})")]
    NoAdapter,
    #[error("no GPU adapter's name contains '{name}' (found: {found}); `hairlab adapters` lists them")]
    NoNamedAdapter { name: String, found: String },
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
    /// `--adapter` or `HAIRLAB_ADAPTER` set to `software` or `hardware` overrides `default`.
    pub fn from_env_or(default: AdapterPreference) -> AdapterPreference {
        match adapter_choice().as_deref() {
            Some("software") => AdapterPreference::Software,
            Some("hardware") => AdapterPreference::Hardware,
            _ => default,
        }
    }
}

/// `--adapter`'s value, set once by the command line.
static ADAPTER_FLAG: OnceLock<String> = OnceLock::new();

/// Makes `choice` (`software`, `hardware` or a part of an adapter's name) the adapter choice of this process, over
/// `HAIRLAB_ADAPTER`; the first call wins.
pub fn set_adapter_choice(choice: &str) {
    let _ = ADAPTER_FLAG.set(choice.to_string());
}

/// The adapter choice: `--adapter`, else `HAIRLAB_ADAPTER`, else none.
pub fn adapter_choice() -> Option<String> {
    ADAPTER_FLAG
        .get()
        .cloned()
        .or_else(|| std::env::var(ADAPTER_ENV).ok())
        .filter(|v| !v.trim().is_empty())
}

/// The adapter name part chosen: an [`adapter_choice`] other than `software` and `hardware`.
pub fn adapter_name_choice() -> Option<String> {
    adapter_choice().filter(|v| v != "software" && v != "hardware")
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

/// The adapters whose name contains `name`, any case.
pub fn adapters_named<'a>(adapters: &'a [wgpu::Adapter], name: &str) -> Vec<&'a wgpu::Adapter> {
    let name = name.to_lowercase();
    adapters
        .iter()
        .filter(|a| a.get_info().name.to_lowercase().contains(&name))
        .collect()
}

/// Picks the adapter by policy among those with [`REQUIRED_FEATURES`] (and, when one is chosen, the name of
/// [`adapter_name_choice`]).
pub fn select_adapter(
    adapters: &[wgpu::Adapter],
    pref: AdapterPreference,
) -> Result<wgpu::Adapter, GpuError> {
    if adapters.is_empty() {
        return Err(GpuError::NoAdapter);
    }
    let named: Vec<&wgpu::Adapter> = match adapter_name_choice() {
        Some(name) => {
            let named = adapters_named(adapters, &name);
            if named.is_empty() {
                return Err(GpuError::NoNamedAdapter {
                    name,
                    found: adapters
                        .iter()
                        .map(|a| a.get_info().name)
                        .collect::<Vec<_>>()
                        .join(", "),
                });
            }
            named
        }
        None => adapters.iter().collect(),
    };
    named
        .into_iter()
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

/// Every adapter of [`backends`], with no window.
pub fn enumerate_adapters() -> Vec<wgpu::Adapter> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: backends(),
        ..wgpu::InstanceDescriptor::new_without_display_handle_from_env()
    });
    pollster::block_on(instance.enumerate_adapters(backends()))
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
        let adapters = enumerate_adapters();
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

    /// [`Gpu::headless`] with storage bindings of at most `bytes` (below the adapter's limit): a device on which
    /// small scenes exercise what splits large buffers over several bindings.
    pub fn headless_with_binding_limit(pref: AdapterPreference, bytes: u64) -> Result<Gpu, GpuError> {
        let adapters = enumerate_adapters();
        let adapter = select_adapter(&adapters, pref)?;
        let info = adapter.get_info();
        let mut desc = device_descriptor(&adapter);
        desc.required_limits.max_storage_buffer_binding_size =
            desc.required_limits.max_storage_buffer_binding_size.min(bytes);
        let (device, queue) =
            pollster::block_on(adapter.request_device(&desc)).map_err(|cause| GpuError::RequestDevice {
                adapter: describe(&info),
                cause,
            })?;
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
