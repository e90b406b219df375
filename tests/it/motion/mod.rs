//! Hair in motion (issue 18): every motion source is deterministic — frame `k` is the same bits whatever was
//! played before, in the simulation and in the rendered image; a baked simulation plays back bit for bit as a
//! sequence; the simulation keeps its invariants (segment lengths, roots on the moving scalp, no point inside
//! the head beyond a stated depth, bounded energy); every bad input is one error naming the file or key.
//! Test-sized: a few hundred strands, tens of frames. A file per concern: frames and their playback (`frames`),
//! the simulation on the CPU and the GPU (`simulation`), bad input (`bad_input`). The test-sized presets they
//! (and `motion_colliders`) share are here.

mod bad_input;
mod frames;
mod simulation;

use hairlab::motion::Motion;
use hairlab::settings::Settings;

/// A motion preset shrunk to test size.
pub(crate) fn small(preset: &str, extra: &[&str]) -> Settings {
    let mut set: Vec<String> = [
        "scene.generator.strands=300",
        "scene.generator.segments=12",
        "render.width=96",
        "render.height=72",
        "render.map_resolution=128",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    set.extend(extra.iter().map(|s| s.to_string()));
    Settings::load_preset(preset, &set).unwrap_or_else(|e| panic!("{preset}: {e:#}"))
}

/// The simulation of a simulated preset's motion.
pub(crate) fn sim(motion: &mut Motion) -> &mut hairlab::motion::Simulation {
    match motion {
        Motion::Simulate(s) => s,
        _ => panic!("a simulated preset"),
    }
}
