//! How a frame is rendered ([`RenderSettings`], the `[render]` preset section), how a strand fragment's alpha
//! is found ([`AlphaMode`]) and how it is shaded ([`ShadingModel`]).

pub use crate::render::caster::{LightStrands, Raster};
pub use crate::shading::{HairModel, ShadingModel};
use serde::{Deserialize, Serialize};

/// How a frame is rendered: output size, light-map resolution, hair material, filtering of the lookups.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderSettings {
    /// Output size of `hairlab render` (the window uses its viewport size).
    pub width: u32,
    pub height: u32,
    /// Side of the square light-space hair maps, 1..=4096.
    pub map_resolution: u32,
    /// Global hair opacity in (0, 1]: every fragment's alpha in `constant` mode, the strands' material opacity
    /// in `coverage` mode.
    pub hair_alpha: f32,
    /// How a fragment's alpha is found ([`AlphaMode`]).
    pub alpha: AlphaMode,
    /// World width of a strand of thickness 1 (`coverage` mode): the width of strands without a thickness array
    /// (the generated ones; a `.hair` header's default thickness is not applied) and the scale on a `.hair`
    /// file's thickness array (1 takes it in the file's units). The default, 1.2 mm, is about one pixel at the
    /// default head's distance at 640×480, so the default head in `coverage` mode looks much as in `constant`
    /// mode, at the same `hair_alpha`.
    pub strand_width: f32,
    /// How a lit strand point is shaded ([`ShadingModel`]: `kajiya-kay`, `marschner`, `dual-scattering` or
    /// `chiang`).
    pub shading: ShadingModel,
    /// How light crosses the strands ([`HairModel`]: `absorber`, today's look, or `fibres`, which takes the
    /// opacity from geometry at material opacity 1, drops the ambient terms and carries light through fibres
    /// as the path tracer's fibre scatters it; under `fibres`, `alpha`, `hair_alpha` and `ambient` are not
    /// read: [`RenderSettings::alpha_mode`], [`RenderSettings::opacity`], [`RenderSettings::ambient_scale`]).
    pub hair_model: HairModel,
    /// Under the fibres model, where the light other than the light's own comes from
    /// ([`crate::shading::mesh_bounce::Probe`]: `voxels`, the voxel density's estimate, or `traced`, the path
    /// tracer's gather at the probe's points; docs/truth.md).
    pub probe: crate::shading::mesh_bounce::Probe,
    /// Colour of strands without their own colour (linear RGB).
    pub hair_color: [f32; 3],
    pub background: [f32; 3],
    /// 3x3 percentage-closer filtering of the shadow method's visibility in the eye passes.
    pub pcf: bool,
    /// Half-texel jitter of the light-map coordinate before every lookup (Sintorn & Assarsson 2009 §3.3).
    pub jitter: bool,
    /// How every light pass and the exact reference draw the strands from the light: `lines`, light-facing
    /// `ribbons` at least one texel wide with a coverage alpha (the anti-aliasing engines apply in the shadow
    /// view), or `auto`, ribbons under the fibres model and lines otherwise ([`LightStrands`]; what is drawn:
    /// [`RenderSettings::strands_drawn`]).
    pub light_strands: LightStrands,
    /// Least width of a light-space ribbon in light texels, 1..=8 (`ribbons` only): a strand thinner is drawn
    /// this wide with its alpha scaled by the covered fraction, so its opacity spreads over more texels and a
    /// sub-texel move changes each texel less.
    pub light_min_width: f32,
    /// How the strand lines become light texels: `hardware` (the GPU's line rasteriser) or `compute` (the compute
    /// rasteriser's fragment stream under its written coverage rule, drawn as points; lines only, so it needs
    /// `light_strands = lines`; [`Raster`]).
    pub raster: Raster,
    /// Under `raster = compute`: 0 rasterises one segment per invocation; a side T in 4..=256 bins the segments
    /// to T×T-texel tiles, each rasterised by a workgroup (the same stream; `render::caster::compute`).
    pub raster_tile: u32,
    /// Light-map supersampling `s`, 1, 2 or 4 (Yuksel & Keyser 2008, §5: multisampling the shadow computation
    /// removes the flicker of aliased strands): every light map, the reference's included, is built at
    /// `map_resolution × s` texels a side ([`RenderSettings::light_map_side`]), and the eye lookup averages the
    /// method's visibility over the `s × s` sub-texels of the point's `map_resolution` texel
    /// ([`crate::visibility::lookup`]). 1 is the plain lookup.
    pub light_supersample: u32,
    /// `raster` (the GPU methods) or `path` (the CPU path-traced reference; `hairlab render` only).
    pub mode: RenderMode,
    /// Samples per pixel under `mode = path`, 1..=[`MAX_SPP`].
    pub spp: u32,
    /// The path tracer's seed: the same seed gives the same image (a second seed gives the noise floor).
    pub seed: u64,
    /// Scale of the raster's ambient terms: every hair fragment adds `0.08 × ambient ×` its colour, every mesh
    /// fragment `0.12 × ambient ×` its colour. 1 is the workbench's look; 0 drops them, as the path tracer has
    /// no environment light (`docs/truth.md`).
    pub ambient: f32,
    /// The effects the path tracer carries under `mode = path` ([`PathEffects`]; all of them by default).
    pub path: PathEffects,
}

/// The path tracer's switches (`render.path.*`), each turning one effect the real-time model approximates off
/// alone (`docs/truth.md`): the defaults are the truth.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PathEffects {
    /// `all` scattering events; `fibres`: all but the light a mesh bounces after the first hit (no light from
    /// the floor onto the hair); `one`: the first hit's direct light only (single scattering).
    pub events: PathEvents,
    /// `traced`: the fibres block shadow rays; `off`: they do not (meshes always do).
    pub hair_shadows: PathHairShadows,
    /// The BSDF at the first hit: `fibre` (Chiang et al. 2016's, and Lambert on meshes), or `raster`: the raster's
    /// shading model (`render.shading`), light and ambient terms at the first hit and nothing after it; or
    /// `isotropic`: the fibre's direct light by Chiang's BSDF, the light arriving from elsewhere scattered alike
    /// every way with one fibre's albedo `ā_f + ā_b` (the fibres model's response to its probe).
    pub first_hit: PathFirstHit,
}

/// `render.path.events`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PathEvents {
    #[default]
    All,
    /// Every event among the fibres; light bounced off a mesh after the first hit is dropped.
    Fibres,
    One,
}

/// `render.path.hair_shadows`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PathHairShadows {
    #[default]
    Traced,
    Off,
}

/// `render.path.first_hit`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PathFirstHit {
    #[default]
    Fibre,
    Raster,
    /// Chiang's direct light at a fibre, the rest of its light scattered alike every way with the albedo the
    /// fibres model's probe response takes.
    Isotropic,
}

/// The most samples per pixel `render.spp` takes.
pub const MAX_SPP: u32 = 65536;

/// Which renderer `hairlab render` runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RenderMode {
    /// The GPU rasteriser with the chosen shadow method and transparency technique.
    #[default]
    Raster,
    /// The CPU path tracer over round fibres (`crate::pathtrace`).
    Path,
}

/// The values `render.light_supersample` takes.
pub const LIGHT_SUPERSAMPLES: [u32; 3] = [1, 2, 4];

impl RenderSettings {
    /// How fragments' alphas are found: `alpha`, or coverage under the fibres model.
    pub fn alpha_mode(&self) -> AlphaMode {
        match self.hair_model {
            HairModel::Absorber => self.alpha,
            HairModel::Fibres => AlphaMode::Coverage,
        }
    }

    /// The strands' material opacity: `hair_alpha`, or 1 under the fibres model (a fibre is opaque; its
    /// coverage makes the alpha).
    pub fn opacity(&self) -> f32 {
        match self.hair_model {
            HairModel::Absorber => self.hair_alpha,
            HairModel::Fibres => 1.0,
        }
    }

    /// The one alpha of a strand over a light texel where a method takes a global alpha (occupancy's
    /// `V = e^(−o b(α))`; each fragment's own coverage is ignored there): `hair_alpha`, or under the fibres model
    /// `1 − e^(−1)`, the Boolean model's one fibre crossed (`light_opacity` in `shaders/common/frame.wgsl`).
    pub fn light_opacity(&self) -> f32 {
        match self.hair_model {
            HairModel::Absorber => self.hair_alpha,
            HairModel::Fibres => 1.0 - crate::visibility::transmittance(1.0),
        }
    }

    /// The scale of the raster's ambient terms: `ambient`, or 0 under the fibres model.
    pub fn ambient_scale(&self) -> f32 {
        match self.hair_model {
            HairModel::Absorber => self.ambient,
            HairModel::Fibres => 0.0,
        }
    }

    /// How the light passes draw the strands: `light_strands` with `auto` resolved ([`LightStrands::drawn`]).
    pub fn strands_drawn(&self) -> LightStrands {
        self.light_strands.drawn(self.hair_model, self.raster)
    }

    /// Texels a side of every light map as built: `map_resolution × light_supersample`.
    pub fn light_map_side(&self) -> u32 {
        self.map_resolution.saturating_mul(self.light_supersample.max(1))
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 480,
            map_resolution: 512,
            hair_alpha: 0.35,
            alpha: AlphaMode::Constant,
            strand_width: DEFAULT_STRAND_WIDTH,
            shading: ShadingModel::KajiyaKay,
            hair_model: HairModel::Absorber,
            probe: crate::shading::mesh_bounce::Probe::Voxels,
            hair_color: [0.30, 0.18, 0.09],
            background: [0.12, 0.13, 0.15],
            pcf: false,
            jitter: false,
            light_strands: LightStrands::Auto,
            light_min_width: 1.0,
            raster: Raster::Hardware,
            raster_tile: 0,
            light_supersample: 1,
            mode: RenderMode::Raster,
            spp: 16,
            seed: 0,
            ambient: 1.0,
            path: PathEffects::default(),
        }
    }
}

/// How a fragment's alpha is found, in the two vertex stages every light-space and eye-space pass shares
/// (`strand_alpha` in `shaders/common/frame.wgsl`), so every technique and shadow method sees the same alphas.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AlphaMode {
    /// The point's alpha times `hair_alpha`, whatever the strand's width and the view.
    #[default]
    Constant,
    /// The strand's coverage of the pixel (eye) or light texel: `clamp(hair_alpha · width / footprint, 0, 1)` times
    /// the point's alpha, width = thickness × `strand_width`, footprint from [`footprint_per_w`] at the
    /// point's depth.
    Coverage,
}

/// Default [`RenderSettings::strand_width`], in world units (metres for the generated scenes).
pub const DEFAULT_STRAND_WIDTH: f32 = 1.2e-3;
