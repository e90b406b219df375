//! Shadow methods behind one trait. Each method is one file; [`registry`] lists them and is the only place that
//! knows them all. The UI's method panel is generated from [`ShadowMethod::params`].

pub mod bom;
pub mod dc;
pub mod dom;
pub mod none;
pub mod occupancy;
pub mod opaque_shadow_map;
pub mod osm;
pub mod reference;
pub mod registry;

use crate::gpu::timing::GpuTimer;
use crate::gpu::{Gpu, GpuError};
use crate::render::geometry::GeometryBuffers;
use crate::render::passes::light_depth::LightDepthMaps;
use crate::visibility::{Fragment, MethodParams};
use std::collections::BTreeMap;

/// The kind and range of one method parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamKind {
    /// A real value in `[min, max]`; `log` asks the UI for a logarithmic slider.
    Float { min: f32, max: f32, log: bool },
    /// An integer in `[min, max]`.
    Int { min: i32, max: i32 },
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
    pub fn check(&self, v: f32) -> Result<(), String> {
        let ok = match self.kind {
            ParamKind::Float { min, max, .. } => v.is_finite() && (min..=max).contains(&v),
            ParamKind::Int { min, max } => v.fract() == 0.0 && (min as f32..=max as f32).contains(&v),
        };
        if ok {
            Ok(())
        } else {
            let range = match self.kind {
                ParamKind::Float { min, max, .. } => format!("a number in [{min}, {max}]"),
                ParamKind::Int { min, max } => format!("an integer in [{min}, {max}]"),
            };
            Err(format!(
                "parameter '{}' = {v} is out of range: expected {range}",
                self.key
            ))
        }
    }
}

/// Parameter values by key; missing keys take the spec's default.
pub type ParamValues = BTreeMap<String, f32>;

/// A hair self-shadowing method: how it turns the light-space view of the strands into visibility `V(z)`.
pub trait ShadowMethod: Sync {
    /// Stable identifier used in presets and on the command line (kebab-case).
    fn name(&self) -> &'static str;
    /// Human-readable name for the UI.
    fn label(&self) -> &'static str;
    /// The paper the method follows (or a one-line description of the baseline).
    fn source(&self) -> &'static str;
    /// The WGSL file under `shaders/` defining `fn visibility_at(texel: vec2<i32>, z: f32) -> f32` over the
    /// method's group-1 resources.
    fn lookup_wgsl(&self) -> &'static str;
    /// Tunable parameters, shown as the method's panel.
    fn params(&self) -> &'static [ParamSpec] {
        &[]
    }
    /// Values for `FrameUniforms::method_params` from the parameter values.
    fn uniform_params(&self, _values: &ParamValues) -> [f32; 4] {
        [0.0; 4]
    }
    /// The CPU model with these parameter values (`None` for the baselines, which define
    /// [`ShadowMethod::visibility`] directly).
    fn model(&self, _values: &ParamValues, _hair_alpha: f32) -> Option<MethodParams> {
        None
    }
    /// CPU model of the method for one texel: visibility at normalised light depth `z` given all the texel's
    /// fragments (the specification the GPU lookup must match).
    fn visibility(&self, values: &ParamValues, hair_alpha: f32, fragments: &[Fragment], z: f32) -> f32 {
        match self.model(values, hair_alpha) {
            Some(m) => m.visibility_curve(fragments, &[z])[0],
            None => 1.0,
        }
    }
    /// Creates the method's GPU state (maps, pipelines, the group-1 bind group its lookup reads).
    fn create_gpu(&self, gpu: &Gpu) -> Box<dyn MethodGpu>;
    /// An on-demand analysis of the exact fragment lists that tunes the method's parameters (e.g. Bounding
    /// Opacity Maps' automatic split ratio); run from the method panel, never per frame.
    fn analysis(&self) -> Option<Analysis> {
        None
    }
}

/// An on-demand computation over the reference's per-texel fragment lists.
#[derive(Clone, Copy)]
pub struct Analysis {
    /// Button label.
    pub label: &'static str,
    pub help: &'static str,
    pub run: fn(&[Vec<crate::render::passes::abuffer::RefFragment>], &ParamValues) -> AnalysisResult,
}

/// What an analysis found: parameter values to apply, a table of scores (first row: header) and a summary.
#[derive(Clone, Debug, PartialEq)]
pub struct AnalysisResult {
    pub apply: ParamValues,
    pub table: Vec<Vec<String>>,
    pub summary: String,
}

/// What a method's light passes can use.
pub struct MethodContext<'a> {
    pub gpu: &'a Gpu,
    /// Group 0 of every light pass: the frame uniforms.
    pub frame_layout: &'a wgpu::BindGroupLayout,
    pub frame_bind_group: &'a wgpu::BindGroup,
    pub geometry: &'a GeometryBuffers,
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

/// A method's GPU side: its maps, the passes that fill them, and the bind group its lookup reads.
pub trait MethodGpu: Send {
    /// (Re)allocates the maps for the current parameters and records the method's light passes.
    fn record(
        &mut self,
        ctx: &MethodContext,
        encoder: &mut wgpu::CommandEncoder,
        timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError>;
    /// Group 1 of the eye passes and of the evaluation pass.
    fn bind_group_layout(&self) -> &wgpu::BindGroupLayout;
    fn bind_group(&self) -> &wgpu::BindGroup;
    /// GPU memory held by the method's maps, in bytes.
    fn memory_bytes(&self) -> u64;
    /// Geometry passes one frame of the method takes (besides the shared light-depth pass).
    fn geometry_passes(&self) -> u32 {
        0
    }
    /// The reference's A-buffer (only the reference has one).
    fn as_reference(&self) -> Option<&crate::render::passes::abuffer::ABuffer> {
        None
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
    /// `bytes_per_texel`: bytes of the shared maps the lookup reads, reported as the method's memory.
    pub fn new(gpu: &Gpu, bytes_per_texel: u64) -> NoMaps {
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
        NoMaps {
            layout,
            bind_group,
            bytes_per_texel,
            bytes: 0,
        }
    }
}

impl MethodGpu for NoMaps {
    fn record(
        &mut self,
        ctx: &MethodContext,
        _encoder: &mut wgpu::CommandEncoder,
        _timer: &mut Option<GpuTimer>,
    ) -> Result<(), GpuError> {
        let res = ctx.map_resolution() as u64;
        self.bytes = res * res * self.bytes_per_texel;
        Ok(())
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
}

/// The value of `spec` in `values`, or its default.
pub fn value(values: &ParamValues, spec: &ParamSpec) -> f32 {
    values.get(spec.key).copied().unwrap_or(spec.default)
}

/// Checks that every key in `values` belongs to `method` and lies in range.
pub fn validate(method: &dyn ShadowMethod, values: &ParamValues) -> Result<(), String> {
    for (k, v) in values {
        let spec = method.params().iter().find(|p| p.key == k).ok_or_else(|| {
            let known: Vec<_> = method.params().iter().map(|p| p.key).collect();
            format!(
                "method '{}' has no parameter '{k}' (it has: {})",
                method.name(),
                known.join(", ")
            )
        })?;
        spec.check(*v)?;
    }
    Ok(())
}
