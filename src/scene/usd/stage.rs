//! Opening a stage — the root file checked as every input is, the crate's cap on each layer set to hairlab's
//! ([`crate::io::MAX_INPUT_BYTES`]), the stage-wide metadata read — and what its composition said: a layer that
//! could not be found or read (sublayer, reference, payload), an arc dropped for a cycle or a chain too deep, each
//! one warning line naming the layer or prim and the arc.

use std::cell::RefCell;
use std::path::Path;

use glam::{DMat4, DVec3, DVec4};
use openusd::usd::Stage;

use super::{Reader, UsdError, token};

/// The longest warning line kept: a deep stage's prim paths run to kilobytes.
const MAX_WARNING_CHARS: usize = 400;

/// The most warning lines kept: a dropped arc is said once per prim composed through it.
const MAX_WARNINGS: usize = 20;

/// Opens the stage and reads its stage-wide metadata.
pub(super) fn open(path: &Path) -> Result<Reader<'_>, UsdError> {
    let stage_err = |cause: String| UsdError::Stage {
        file: path.to_owned(),
        cause,
    };
    let meta = std::fs::metadata(path).map_err(|e| stage_err(e.to_string()))?;
    if !meta.is_file() {
        return Err(stage_err("not a regular file".into()));
    }
    if meta.len() > crate::io::MAX_INPUT_BYTES {
        return Err(stage_err(format!(
            "{} bytes, more than the {} bytes hairlab reads",
            meta.len(),
            crate::io::MAX_INPUT_BYTES
        )));
    }
    let name = path
        .to_str()
        .ok_or_else(|| stage_err("the path is not UTF-8 (the USD crate opens UTF-8 paths only)".into()))?;
    // Every layer the stage brings in (sublayers, references, payloads) is read under the cap the root is.
    openusd::ar::set_max_asset_bytes(crate::io::MAX_INPUT_BYTES);
    let stage = Stage::open(name).map_err(|e| stage_err(format!("{e:#}")))?;
    let meta = |key: &str| {
        stage
            .stage_metadata(key)
            .map_err(|e| stage_err(format!("{key}: {e:#}")))
    };
    let up_axis = match meta("upAxis")? {
        None => 'Y',
        Some(v) => match token(&v) {
            Some("Y") => 'Y',
            Some("Z") => 'Z',
            _ => return Err(stage_err(format!("upAxis: {v:?}; a stage is Y-up or Z-up"))),
        },
    };
    let meters_per_unit = match meta("metersPerUnit")? {
        None => 0.01,
        Some(v) => match v.clone().try_as_double() {
            Some(m) if m.is_finite() && m > 0.0 => m,
            _ => {
                return Err(stage_err(format!(
                    "metersPerUnit: {v:?}; it must be finite and above 0"
                )));
            }
        },
    };
    let tcps = stage.time_codes_per_second();
    if !(tcps.is_finite() && tcps > 0.0) {
        return Err(stage_err(format!(
            "timeCodesPerSecond is {tcps}; it must be finite and above 0"
        )));
    }
    let axis = match up_axis {
        'Z' => DMat4::from_cols(DVec4::X, DVec4::NEG_Z, DVec4::Y, DVec4::W),
        _ => DMat4::IDENTITY,
    };
    Ok(Reader {
        file: path,
        stage,
        to_world: DMat4::from_scale(DVec3::splat(meters_per_unit)) * axis,
        up_axis,
        meters_per_unit,
        worlds: RefCell::default(),
    })
}

/// The stage's composition warnings so far (every prim walked has been composed), one line each, in the crate's
/// order, without repeats; past [`MAX_WARNINGS`], one last line counts the rest.
pub(super) fn warnings(r: &Reader) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut more = 0;
    for e in r.stage.composition_errors() {
        let mut line = e.to_string().replace('\n', " ");
        if line.chars().count() > MAX_WARNING_CHARS {
            line = line.chars().take(MAX_WARNING_CHARS).collect::<String>() + "…";
        }
        if out.contains(&line) {
            continue;
        }
        if out.len() < MAX_WARNINGS {
            out.push(line);
        } else {
            more += 1;
        }
    }
    if more > 0 {
        out.push(format!("… and {more} more composition warnings"));
    }
    out
}
