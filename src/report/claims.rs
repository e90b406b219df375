//! The papers' claims a study's tables can check, each one function from the measured figures to a verdict:
//! the claims tests (`tests/it/motion_claims.rs` MC-1, `tests/it/transparency_claims.rs` TC-1) assert these
//! verdicts, and the report shows them, so the page and the tests judge with the same code and thresholds.

use super::data::Study;
use super::page::{escape, section};
use crate::measure::MethodConfig;
use crate::methods::LightMethod;
use crate::methods::dom::Dom;
use crate::methods::occupancy::Occupancy;
use crate::render::transparency::EyeTransparency;
use crate::render::transparency::occupancy_order::OccupancyOrder;
use crate::render::transparency::weighted_average::WeightedAverage;
use std::fmt::Write as _;

/// One claim as measured on a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Claim {
    pub id: &'static str,
    /// The paper and the figure or section the claim comes from.
    pub source: &'static str,
    pub statement: &'static str,
    /// What the paper shows.
    pub paper: &'static str,
    /// What hairlab measured.
    pub measured: String,
    pub holds: bool,
}

/// The Deep Opacity Maps configuration MC-1 reads: three layers, as the sweep test measures it.
pub fn mc1_dom_label() -> String {
    MethodConfig::new(Dom.name(), [("layers".to_string(), 3.0)].into()).label()
}

/// How many times occupancy maps' pop rate Deep Opacity Maps' must reach for MC-1 to hold.
pub const MC1_POP_RATIO: f64 = 2.5;
/// TC-1 holds when occupancy ordering's hair-pixel RMSE is below this share of weighted average's.
pub const TC1_RMSE_SHARE: f64 = 0.5;

/// MC-1 (Sintorn & Assarsson 2009, Fig. 4 in motion): a stray strand sweeping in front of a clump pops Deep
/// Opacity Maps' shadow several times as often as occupancy maps' (`dom_pop_rate` against
/// `occupancy_pop_rate`; undefined, and so not holding, when occupancy maps never pop).
pub fn mc1(dom_label: &str, dom_pop_rate: f64, occupancy_pop_rate: f64) -> Claim {
    let holds = occupancy_pop_rate > 0.0 && dom_pop_rate > MC1_POP_RATIO * occupancy_pop_rate;
    Claim {
        id: "MC-1",
        source: "Sintorn & Assarsson 2009, Fig. 4 (in motion)",
        statement: "a sweeping stray strand makes Deep Opacity Maps' shadow pop several times as often as \
                    occupancy maps'",
        paper: "layers restart where the stray strand passes (Fig. 4); occupancy maps keep the depth range",
        measured: format!(
            "pop rate {dom_label} {:.3} % against occupancy {:.3} % (ratio needed > {MC1_POP_RATIO})",
            100.0 * dom_pop_rate,
            100.0 * occupancy_pop_rate
        ),
        holds,
    }
}

/// TC-1 (Sintorn & Assarsson 2009, §3.4 and Fig. 2): occupancy ordering is far closer to the exact composite
/// than weighted average: less than [`TC1_RMSE_SHARE`] of its hair-pixel RMSE.
pub fn tc1(occupancy_rmse: f64, weighted_average_rmse: f64) -> Claim {
    Claim {
        id: "TC-1",
        source: "Sintorn & Assarsson 2009, §3.4, Fig. 2",
        statement: "occupancy-ordered blending is nearly exact; weighted average is visibly off",
        paper: "Fig. 2: occupancy ordering next to the sorted reference, weighted average dull",
        measured: format!(
            "hair-pixel RMSE occupancy-order {occupancy_rmse:.5} against weighted-average \
             {weighted_average_rmse:.5} (needed below {TC1_RMSE_SHARE} of it)"
        ),
        holds: occupancy_rmse < TC1_RMSE_SHARE * weighted_average_rmse,
    }
}

/// The claims `study`'s tables hold the figures of: MC-1 where the motion measured `dom:layers=3` and
/// `occupancy`, TC-1 where the transparency bench measured `occupancy-order` and `weighted-average` at their
/// defaults.
pub fn of_study(study: &Study) -> Vec<Claim> {
    let mut out = Vec::new();
    if let Some(m) = &study.motion {
        let t = &m.summary;
        let pop = |label: &str| {
            (0..t.rows.len())
                .find(|&i| t.text(i, "config") == Some(label))
                .and_then(|i| t.number(i, "pop_rate"))
        };
        let dom = mc1_dom_label();
        if let (Some(d), Some(occ)) = (pop(&dom), pop(Occupancy.name())) {
            out.push(mc1(&dom, d, occ));
        }
    }
    if let Some(tr) = &study.transparency {
        let t = &tr.table;
        let rmse = |label: &str| {
            (0..t.rows.len())
                .find(|&i| t.text(i, "configuration") == Some(label))
                .and_then(|i| t.number(i, "rmse_hair"))
        };
        if let (Some(occ), Some(wa)) = (rmse(OccupancyOrder.name()), rmse(WeightedAverage.name())) {
            out.push(tc1(occ, wa));
        }
    }
    out
}

/// The claims table, or nothing when the study checks none.
pub fn claims(study: &Study) -> Option<String> {
    let claims = of_study(study);
    if claims.is_empty() {
        return None;
    }
    let mut content = String::from(
        "<div class=\"scroll\"><table id=\"claims\">\n<caption>The papers' claims on this scene</caption>\n\
         <thead><tr><th scope=\"col\">claim</th><th scope=\"col\">paper and figure</th><th scope=\"col\">statement\
         </th><th scope=\"col\">the paper</th><th scope=\"col\">measured here</th><th scope=\"col\">holds</th>\
         </tr></thead>\n<tbody>\n",
    );
    for c in &claims {
        let (class, word) = if c.holds {
            ("holds", "yes")
        } else {
            ("fails", "no")
        };
        let _ = writeln!(
            content,
            "<tr><th scope=\"row\">{}</th><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"{class}\">{word}\
             </td></tr>",
            c.id,
            escape(c.source),
            escape(c.statement),
            escape(c.paper),
            escape(&c.measured)
        );
    }
    content.push_str("</tbody>\n</table></div>\n");
    Some(section("claims", "The papers' claims", &content))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_follow_the_thresholds() {
        assert!(mc1(&mc1_dom_label(), 0.008, 0.0022).holds);
        assert!(!mc1(&mc1_dom_label(), 0.005, 0.0022).holds);
        assert!(!mc1(&mc1_dom_label(), 0.008, 0.0).holds);
        assert!(tc1(0.01, 0.03).holds);
        assert!(!tc1(0.02, 0.03).holds);
    }
}
