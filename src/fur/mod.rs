//! Hybrid fur (Andersen et al. 2016), the CPU half: a base mesh welded, oriented and neighboured
//! ([`mesh`]), extruded into a prismatic shell with dynamic resolution ([`shell`]), its sub-elements indexed
//! by eqs. (1)–(3) ([`index`]), the paper's generated base meshes ([`shapes`]), the simplex noise ([`noise`])
//! the volume densities and tangents come from ([`volume`]), the ray march through them ([`march`]), the
//! explicit guard hairs on the base mesh ([`guard`]), the combination of typed fragments ([`blend`]), the
//! `[fur]` settings with the fur of a scene ([`settings`]) and the paper's Table 1 for a frame ([`table`]). The
//! specification is
//! `shared/specs/transparency-and-fur.md` Part B; the GPU ray march mirrors these functions.

pub mod blend;
pub mod guard;
pub mod index;
pub mod march;
pub mod mesh;
pub mod noise;
pub mod settings;
pub mod shapes;
pub mod shell;
pub mod table;
pub mod volume;
