//! The plug-in contract between the renderer and the shadow methods: what a method is ([`MethodInfo`], its
//! parameters), what the renderer asks of it ([`LightMethod`]), and its GPU state ([`MethodGpu`]) with what its
//! light passes can use ([`MethodContext`]). The renderer defines it; `crate::methods` implements it from above
//! (nothing here knows a method).

use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError};
use crate::render::caster::{LightCaster, LightStage};
use crate::render::passes::light_depth::LightDepthMaps;
use std::collections::BTreeMap;

/// The kind and range of one method parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamKind {
    /// A real value in `[min, max]`; `log` asks the UI for a logarithmic slider.
    Float { min: f32, max: f32, log: bool },
    /// An integer in `[min, max]`.
    Int { min: i32, max: i32 },
    /// One of named options, stored as its index (a combo box in the panel, the word in presets and on the
    /// command line; the index is accepted too, so older numeric presets still load).
    Choice { options: &'static [&'static str] },
}

/// A parameter key or value that a method or technique does not take; the message names the key.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ParamError {
    #[error("parameter '{key}' = {value} is out of range: expected {expected}")]
    OutOfRange {
        key: &'static str,
        value: f32,
        expected: String,
    },
    #[error("parameter '{key}': '{text}' is not one of {options}")]
    NotAChoice {
        key: &'static str,
        text: String,
        options: String,
    },
    #[error("parameter '{key}': '{text}' is not a number")]
    NotANumber { key: &'static str, text: String },
    #[error("{family} '{name}' has no parameter '{key}' (it has: {known})")]
    UnknownKey {
        family: &'static str,
        name: &'static str,
        key: String,
        known: String,
    },
}

/// A name that no registry entry has; the message lists the known names.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown {family} '{name}' (known: {known})")]
pub struct UnknownName {
    /// What was looked up: "shadow method", "transparency technique".
    pub family: &'static str,
    pub name: String,
    pub known: String,
}

/// One tunable parameter of a method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    pub key: &'static str,
    pub label: &'static str,
    pub help: &'static str,
    pub kind: ParamKind,
    pub default: f32,
}

impl ParamSpec {
    /// Checks `v` against the parameter's range (and integrality).
    pub fn check(&self, v: f32) -> Result<(), ParamError> {
        let ok = match self.kind {
            ParamKind::Float { min, max, .. } => v.is_finite() && (min..=max).contains(&v),
            ParamKind::Int { min, max } => v.fract() == 0.0 && (min as f32..=max as f32).contains(&v),
            ParamKind::Choice { options } => v.fract() == 0.0 && v >= 0.0 && (v as usize) < options.len(),
        };
        if ok {
            Ok(())
        } else {
            let range = match self.kind {
                ParamKind::Float { min, max, .. } => format!("a number in [{min}, {max}]"),
                ParamKind::Int { min, max } => format!("an integer in [{min}, {max}]"),
                ParamKind::Choice { options } => format!("one of {}", options.join(", ")),
            };
            Err(ParamError::OutOfRange {
                key: self.key,
                value: v,
                expected: range,
            })
        }
    }

    /// Parses a value as written in a preset or on the command line: a number, or for a choice its word (or
    /// its index).
    pub fn parse(&self, text: &str) -> Result<f32, ParamError> {
        let text = text.trim();
        if let ParamKind::Choice { options } = self.kind
            && let Some(i) = options.iter().position(|o| *o == text)
        {
            return Ok(i as f32);
        }
        let v: f32 = text.parse().map_err(|_| match self.kind {
            ParamKind::Choice { options } => ParamError::NotAChoice {
                key: self.key,
                text: text.to_string(),
                options: options.join(", "),
            },
            _ => ParamError::NotANumber {
                key: self.key,
                text: text.to_string(),
            },
        })?;
        self.check(v)?;
        Ok(v)
    }

    /// The value as a preset writes it: the word of a choice, the number otherwise.
    pub fn format(&self, v: f32) -> String {
        match self.kind {
            ParamKind::Choice { options } if v >= 0.0 && (v as usize) < options.len() => {
                options[v as usize].to_string()
            }
            _ => v.to_string(),
        }
    }

    /// A choice's options (empty for other kinds).
    pub fn options(&self) -> &'static [&'static str] {
        match self.kind {
            ParamKind::Choice { options } => options,
            _ => &[],
        }
    }

    /// The option chosen by `v` (a choice parameter's value), or `None` for other kinds or an invalid index.
    pub fn option(&self, v: f32) -> Option<&'static str> {
        match self.kind {
            ParamKind::Choice { options } if v >= 0.0 => options.get(v as usize).copied(),
            _ => None,
        }
    }
}

/// Parameter values by key; missing keys take the spec's default. A choice holds its option's index.
pub type ParamValues = BTreeMap<String, f32>;

/// What a method is for the comparisons.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A bound on the problem (no shadow, opaque shadow): measured, but not a transparency model to inspect.
    Baseline,
    /// The exact answer every other method is measured against.
    Reference,
    /// An approximation of the reference: inspected, swept and charted.
    Approximation,
}

/// A method's constant description: the registry, the panel, the charts and the tests read it.
#[derive(Clone, Copy, Debug)]
pub struct MethodInfo {
    /// Stable identifier used in presets and on the command line (kebab-case).
    pub name: &'static str,
    /// Human-readable name for the UI.
    pub label: &'static str,
    /// The paper the method follows (or a one-line description of the baseline).
    pub paper: &'static str,
    pub role: Role,
    /// The WGSL file under `shaders/` defining `fn visibility_at(texel: vec2<i32>, z: f32) -> f32` over the
    /// method's group-1 resources.
    pub lookup_wgsl: &'static str,
    /// The WGSL files under `shaders/` of the method's own light passes (none for a method that reads only
    /// the shared maps).
    pub light_wgsl: &'static [&'static str],
    /// Tunable parameters, shown as the method's panel.
    pub params: &'static [ParamSpec],
    /// The method's colour in every plot and chart (inspector, window chart, PNG/SVG), sRGB.
    pub color: [u8; 3],
    /// Largest |V_gpu - V_cpu| the GPU = CPU tests allow: f32 rounding of sums taken in another order, and the
    /// method's own sensitivity to it (stated per method).
    pub gpu_tolerance: f32,
    /// Share of the GPU = CPU samples allowed beyond `gpu_tolerance` (0 for every method whose model is continuous
    /// in the last bits of its inputs).
    pub gpu_outliers: f64,
}

/// A Rust uniform struct and the WGSL struct it mirrors: its name, size and `(field, byte offset)` list, which
/// a test checks against naga's layout of every shader that declares it. Build it with [`uniform_mirror!`].
#[derive(Clone, Debug, PartialEq)]
pub struct UniformMirror {
    pub wgsl_name: &'static str,
    pub size: usize,
    pub fields: Vec<(&'static str, usize)>,
}

/// `uniform_mirror!("WgslName", RustType { field, ... })`: a [`UniformMirror`] whose field names are the Rust
/// field names (so the WGSL struct must use the same names).
#[macro_export]
macro_rules! uniform_mirror {
    ($wgsl:literal, $ty:ty { $($field:ident),* $(,)? }) => {
        $crate::render::method::UniformMirror {
            wgsl_name: $wgsl,
            size: ::std::mem::size_of::<$ty>(),
            fields: vec![$((stringify!($field), ::std::mem::offset_of!($ty, $field))),*],
        }
    };
}

/// What the renderer asks of a shadow method: its constants, its uniform values and its GPU state. The CPU and
/// bench side (`crate::methods::ShadowMethod`) builds on it.
pub trait LightMethod: Sync {
    /// The method's constants.
    fn info(&self) -> &'static MethodInfo;
    fn name(&self) -> &'static str {
        self.info().name
    }
    fn label(&self) -> &'static str {
        self.info().label
    }
    fn lookup_wgsl(&self) -> &'static str {
        self.info().lookup_wgsl
    }
    fn params(&self) -> &'static [ParamSpec] {
        self.info().params
    }
    /// Values for `FrameUniforms::method_params` from the parameter values.
    fn uniform_params(&self, _values: &ParamValues) -> [f32; 4] {
        [0.0; 4]
    }
    /// The method's own uniform struct and its WGSL twin (`None` when it has none).
    fn uniform_mirror(&self) -> Option<UniformMirror> {
        None
    }
    /// Creates the method's GPU state (maps for `ctx`'s parameters and resolution, pipelines, the group-1 bind
    /// group its lookup reads).
    fn create_gpu(&self, ctx: &MethodContext) -> Result<Box<dyn MethodGpu>, GpuError>;
}

/// What a method's light passes can use.
pub struct MethodContext<'a> {
    pub gpu: &'a Gpu,
    /// Group 0 of every light pass: the frame uniforms.
    pub frame_layout: &'a wgpu::BindGroupLayout,
    pub frame_bind_group: &'a wgpu::BindGroup,
    /// What the light passes draw (see [`crate::render::caster`]).
    pub casters: &'a [&'a dyn LightCaster],
    /// The vertex stage of `casters`, which every light pipeline is built for.
    pub light: &'a LightStage,
    /// Nearest and furthest strand depth per texel, already rendered this frame.
    pub light_maps: &'a LightDepthMaps,
    pub values: &'a ParamValues,
    pub hair_alpha: f32,
}

impl MethodContext<'_> {
    pub fn map_resolution(&self) -> u32 {
        self.light_maps.near.width()
    }
}

/// A method's GPU side: its maps, the passes that fill them, and the bind group its lookup reads. It is created
/// with its maps for the first frame's parameters ([`LightMethod::create_gpu`]), so its bind group always
/// exists; each frame, the first included, [`MethodGpu::prepare`] re-allocates what the parameters or the
/// resolution changed and uploads the uniforms, then [`MethodGpu::record`] records the light passes.
pub trait MethodGpu: Send {
    /// Re-allocates the maps when the parameters or the map resolution need other ones; uploads uniforms. A
    /// method that sizes its buffers from the scene runs (and times, in `timer`) its counting passes here.
    fn prepare(&mut self, ctx: &MethodContext, timer: &mut Option<GpuTimer>) -> Result<(), GpuError>;
    /// Records the method's light passes (after [`MethodGpu::prepare`] with the same context).
    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    );
    /// Group 1 of the eye passes and of the evaluation pass.
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout;
    fn bind_group(&self) -> &wgpu::BindGroup;
    /// GPU memory held by the method's maps, in bytes.
    fn memory_bytes(&self) -> u64;
    /// The part of [`MethodGpu::memory_bytes`] that is the shared light-depth maps the lookup reads (held by
    /// the renderer, not by the method): the renderer's memory total counts the rest.
    fn shared_bytes(&self) -> u64 {
        0
    }
    /// GPU memory the method builds its maps from each frame but its lookup does not read (e.g. the exact
    /// fragment lists that adaptive volumetric and compressed deep shadow maps compress): not part of
    /// [`MethodGpu::memory_bytes`], counted in the renderer's total.
    fn build_bytes(&self) -> u64 {
        0
    }
    /// Geometry passes one frame of the method takes (besides the shared light-depth pass).
    fn geometry_passes(&self) -> u32 {
        0
    }
}

/// GPU state of a method whose lookup reads only the shared light-depth maps: an empty group 1.
pub struct NoMaps {
    layout: wgpu::BindGroupLayout,
    bind_group: wgpu::BindGroup,
    bytes_per_texel: u64,
    bytes: u64,
}

impl NoMaps {
    /// `bytes_per_texel`: bytes of the shared maps the lookup reads, reported as the method's (shared) memory.
    pub fn create(ctx: &MethodContext, bytes_per_texel: u64) -> Result<Box<dyn MethodGpu>, GpuError> {
        let gpu = ctx.gpu;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("hairlab.method.empty_layout"),
                entries: &[],
            });
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("hairlab.method.empty_bind_group"),
            layout: &layout,
            entries: &[],
        });
        let res = ctx.map_resolution() as u64;
        Ok(Box::new(NoMaps {
            layout,
            bind_group,
            bytes_per_texel,
            bytes: res * res * bytes_per_texel,
        }))
    }
}

impl MethodGpu for NoMaps {
    fn prepare(&mut self, ctx: &MethodContext, _timer: &mut Option<GpuTimer>) -> Result<(), GpuError> {
        let res = ctx.map_resolution() as u64;
        self.bytes = res * res * self.bytes_per_texel;
        Ok(())
    }
    fn record(
        &mut self,
        _ctx: &MethodContext,
        _encoder: &mut wgpu::CommandEncoder,
        _timer: &mut Option<GpuTimer>,
    ) {
    }
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }
    fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
    }
    fn memory_bytes(&self) -> u64 {
        self.bytes
    }
    fn shared_bytes(&self) -> u64 {
        self.bytes
    }
}

/// The value of `spec` in `values`, or its default.
pub fn value(values: &ParamValues, spec: &ParamSpec) -> f32 {
    values.get(spec.key).copied().unwrap_or(spec.default)
}

/// The option `values` choose for the choice parameter `spec`, as its word (`""` for no option), so a method
/// matches on the words its spec lists rather than on indices.
pub fn choice(values: &ParamValues, spec: &ParamSpec) -> &'static str {
    spec.option(value(values, spec)).unwrap_or("")
}
