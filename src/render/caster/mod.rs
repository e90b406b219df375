//! Light casters: the geometry every light pass (the shared light-depth pass, the exact reference, each
//! method's own passes) draws from the light. A caster feeds the shared light vertex stage
//! (`shaders/common/light_vertex.wgsl`) through its own vertex stage (`shaders/casters/<name>.wgsl`, pasted at
//! `#include_caster`), whose light-fragment contract (normalised light depth, alpha, segment id) is the
//! interface between casters and methods, so a method never knows what it shadows. Light pipelines are built
//! for a caster's [`CasterStage`] (the stage is the key, as in a specialised pipeline: the base descriptor of
//! [`LightStage::pipeline`] adjusted by the stage's topology, vertex buffers and bind groups). That contract is
//! [`stage`], which the casters and the passes import; this file only chooses the caster a setting names.
//!
//! The strands are drawn from the light by one of [`LightStrands`]: as lines ([`lines`]) or as light-facing
//! ribbons with a minimum width of one texel and a coverage alpha ([`ribbons`], the anti-aliasing engines apply
//! in the shadow view). Every light pass and the reference draw the same casters, so the reference stays exact
//! for what the methods see.
//!
//! How the strand lines become light texels is [`Raster`]: the GPU's line rasteriser, or the compute rasteriser
//! ([`compute`]) whose fragment stream (under the written coverage rule of [`raster_model`]) is drawn as points.

pub mod compute;
pub mod lines;
pub mod raster_model;
pub mod ribbons;
pub mod stage;

use serde::{Deserialize, Serialize};
pub use stage::{CasterStage, LightCaster, LightStage, draw_casters};

/// How the strands are drawn from the light (`render.light_strands`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LightStrands {
    /// Whichever the hair model draws its width with ([`LightStrands::drawn`]): ribbons under the fibres model
    /// (a fibre's coverage of its texel is its width, which a line does not draw), lines under the absorber
    /// model or the compute rasteriser.
    #[default]
    Auto,
    /// One line per segment ([`lines::LINES`]): a strand thinner than a texel covers a texel or not as the
    /// rasteriser's line rule decides.
    Lines,
    /// Light-facing ribbons at least one texel wide, alpha scaled by the covered fraction ([`ribbons::RIBBONS`]).
    Ribbons,
}

impl LightStrands {
    /// The choices a setting offers.
    pub const SETTINGS: [LightStrands; 3] = [LightStrands::Auto, LightStrands::Lines, LightStrands::Ribbons];
    /// What the light passes draw ([`LightStrands::drawn`] never gives `Auto`).
    pub const ALL: [LightStrands; 2] = [LightStrands::Lines, LightStrands::Ribbons];

    /// What the light passes draw under `hair` and `raster`: `Auto` resolved, the rest as they are. Under the
    /// fibres model a light fragment's alpha is its strand's coverage of the texel, which ribbons draw across the
    /// strand's width and lines only in the texel the line marks (`docs/truth.md`, "The light map's strands at
    /// their width": on `back-lit` the map passed 1.51× the traced fibres' light with lines, 1.17× with
    /// ribbons); the compute rasteriser draws lines only.
    pub fn drawn(self, hair: crate::shading::HairModel, raster: Raster) -> LightStrands {
        match (self, hair, raster) {
            (LightStrands::Auto, crate::shading::HairModel::Fibres, Raster::Hardware) => {
                LightStrands::Ribbons
            }
            (LightStrands::Auto, _, _) => LightStrands::Lines,
            (s, _, _) => s,
        }
    }

    /// The vertex stage of strands drawn this way; `Auto`, which [`LightStrands::drawn`] resolves before a
    /// caster is chosen, as lines (what it resolves to under the default hair model).
    pub fn stage(self) -> &'static CasterStage {
        match self {
            LightStrands::Auto | LightStrands::Lines => &lines::LINES,
            LightStrands::Ribbons => &ribbons::RIBBONS,
        }
    }

    /// The setting's word.
    pub fn word(self) -> &'static str {
        match self {
            LightStrands::Auto => "auto",
            LightStrands::Lines => "lines",
            LightStrands::Ribbons => "ribbons",
        }
    }
}

/// How the strand lines become light texels (`render.raster`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Raster {
    /// The GPU's line rasteriser ([`lines::LINES`], or the ribbons' triangles).
    #[default]
    Hardware,
    /// The compute rasteriser ([`compute::COMPUTE`]): lines only, under the coverage rule of [`raster_model`].
    Compute,
}

impl Raster {
    pub const ALL: [Raster; 2] = [Raster::Hardware, Raster::Compute];

    /// The setting's word.
    pub fn word(self) -> &'static str {
        match self {
            Raster::Hardware => "hardware",
            Raster::Compute => "compute",
        }
    }

    /// The vertex stage of the strands drawn as `strands` by this rasteriser, or the error naming the keys when
    /// the combination is not drawn (the compute rasteriser lines strands only).
    pub fn stage(self, strands: LightStrands) -> Result<&'static CasterStage, String> {
        match (self, strands) {
            (Raster::Hardware, s) => Ok(s.stage()),
            (Raster::Compute, LightStrands::Lines | LightStrands::Auto) => Ok(&compute::COMPUTE),
            (Raster::Compute, s) => Err(format!(
                "render.raster = compute rasterises the strands as lines; render.light_strands = {} needs \
                 render.raster = hardware",
                s.word()
            )),
        }
    }
}

/// Every caster's vertex stage (what the shader tests compose every light pass with).
pub const ALL_STAGES: [&CasterStage; 3] = [&lines::LINES, &ribbons::RIBBONS, &compute::COMPUTE];
