//! The curves' CSV export: every curve shown (the inspected texel's and each pin's), evaluated at every plotted
//! depth of every texel.

use super::curves::TexelCurves;
use crate::visibility::{self, TexelModel};
use std::path::Path;

/// The ray-traced curve's column (after the texel's reference count, when traced).
const CSV_TRACED: &str = "ray-traced";

impl TexelCurves {
    /// The depths of the CSV: every plotted depth of every texel, sorted, once each.
    pub fn csv_depths(&self) -> Vec<f32> {
        let mut zs: Vec<f32> = self
            .current
            .iter()
            .chain(&self.pins)
            .flat_map(|t| t.depths.iter().copied())
            .collect();
        zs.sort_by(f32::total_cmp);
        zs.dedup();
        zs
    }

    /// CSV `depth,reference,reference count,[ray-traced,]<method>,<method> count...,pin1 reference,pin1 reference
    /// count,...`: every curve shown and its hair count beside it, evaluated at [`TexelCurves::csv_depths`]; the
    /// ray-traced `V` of the fibres ([`super::traced::TRACED_RAYS`]² rays) after a texel's reference where it was traced.
    pub fn csv(&self) -> anyhow::Result<String> {
        let zs = self.csv_depths();
        let mut header = vec!["depth".to_string()];
        let mut columns: Vec<Vec<f32>> = Vec::new();
        let texels = self.current.iter().map(|t| (String::new(), t)).chain(
            self.pins
                .iter()
                .enumerate()
                .map(|(i, t)| (format!("pin{} ", i + 1), t)),
        );
        for (prefix, t) in texels {
            header.push(format!("{prefix}reference"));
            columns.push(visibility::Reference.curve(&t.fragments, &zs));
            header.push(format!("{prefix}reference count"));
            columns.push(visibility::Reference.count_curve(&t.fragments, &zs, t.hair_alpha));
            if let Some(traced) = &t.traced {
                header.push(format!("{prefix}{CSV_TRACED}"));
                columns.push(traced.rays.curve(&zs));
            }
            for m in &t.methods {
                header.push(format!("{prefix}{}", m.label));
                columns.push(m.model.model.curve(&t.fragments, &zs));
                header.push(format!("{prefix}{} count", m.label));
                columns.push(m.model.model.count_curve(&t.fragments, &zs, t.hair_alpha));
            }
        }
        let rows = zs.iter().enumerate().map(|(i, z)| {
            std::iter::once(z.to_string())
                .chain(columns.iter().map(|c| c[i].to_string()))
                .collect::<Vec<_>>()
        });
        crate::io::csv_table("the texel curves", &header, rows)
    }
}

/// Writes `curves` as CSV to `path`: the status line's message on success (with the number of depths), the error
/// line otherwise.
pub fn export(curves: Option<&TexelCurves>, path: &Path) -> Result<String, String> {
    let curves = curves
        .filter(|c| c.current.is_some() || !c.pins.is_empty())
        .ok_or("texel inspector: nothing to export (select a texel first)")?;
    let rows = curves.csv_depths().len();
    curves
        .csv()
        .and_then(|text| crate::io::write_atomic(path, text.as_bytes()))
        .map(|()| format!("curves exported: {} ({rows} depths)", path.display()))
        .map_err(|e| format!("curve export failed: {e:#}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::inspector::TexelPlot;

    fn texel(fragment: (f32, f32), depths: &[f32]) -> TexelPlot {
        TexelPlot {
            label: "t".into(),
            fragments: vec![fragment.into()],
            near: fragment.0,
            far: fragment.0,
            depths: depths.to_vec(),
            reference: Vec::new(),
            reference_count: Vec::new(),
            reference_error: None,
            hair_alpha: 0.5,
            methods: Vec::new(),
            traced: None,
            color: None,
        }
    }

    #[test]
    fn csv_holds_every_texel_at_every_plotted_depth() {
        let curves = TexelCurves {
            current: Some(texel((0.2, 0.5), &[0.1, 0.3])),
            stored: None,
            pins: vec![texel((0.25, 0.75), &[0.3, 0.4])],
        };
        let text = curves.csv().unwrap();
        let mut lines = text.lines();
        assert_eq!(
            lines.next(),
            Some("depth,reference,reference count,pin1 reference,pin1 reference count")
        );
        let rows: Vec<Vec<f32>> = lines
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        // V(z) = exp(-sum of b) over the fragments before z: 1 before the fragment, 1 - alpha after it; the count
        // beside each: 0 strands in front, then 1.
        let want = [
            [0.1, 1.0, 0.0, 1.0, 0.0],
            [0.3, 0.5, 1.0, 0.25, 1.0],
            [0.4, 0.5, 1.0, 0.25, 1.0],
        ];
        assert_eq!(rows.len(), want.len());
        for (row, want) in rows.iter().zip(want) {
            for (got, want) in row.iter().zip(want) {
                assert!((got - want).abs() < 1e-6, "{row:?} vs {want:?}");
            }
        }

        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("curves.csv");
        let message = export(Some(&curves), &path).unwrap();
        assert!(message.contains("(3 depths)"), "{message}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
        let nothing = TexelCurves::default();
        for c in [None, Some(&nothing)] {
            let e = export(c, &path).unwrap_err();
            assert!(e.contains("nothing to export"), "{e}");
        }
    }
}
