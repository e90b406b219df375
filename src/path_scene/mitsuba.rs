//! A still scene as Mitsuba 3 renders it (`hairlab export --format mitsuba`): `scene.xml` with the path tracer's
//! camera, film, light, integrator and fibre BSDF, `hair.txt` (Mitsuba's `linearcurve` file: `x y z radius` per
//! point, a blank line between strands, so round linear curves as `fibre.rs` traces them) and one OBJ per mesh.
//!
//! The mapping, one to one with `path_scene/mod.rs`: the camera's eye, target and +Y up as a `perspective` sensor's
//! `lookat` with `fov_axis = y`; a `box` pixel filter (hairlab jitters uniformly in each pixel); the light's
//! direction and π × colour × intensity as a `directional` emitter's `irradiance`, or a spot light as a `spot`
//! emitter of the same position, axis, intensity, beam width and cutoff (`path_scene::light`, `pathtrace/light.rs`); the fibre as Mitsuba's `hair`
//! BSDF (Chiang et al. 2016) with hairlab's absorption `sigma_a` (per unit radius, as both implementations read it),
//! roughness, cuticle tilt in degrees and index of refraction; meshes as a `twosided` `diffuse` with the mesh colour
//! and `face_normals` (hairlab flat-shades triangles); the `path` integrator with `max_depth` = bounces + 1
//! (Mitsuba counts the segment to the light). Russian roulette differs (Mitsuba's from depth 5, hairlab's from 4
//! bounces) and changes only the noise.

use anyhow::Result;
use std::fmt::Write;
use std::path::{Path, PathBuf};

use crate::pathtrace::bsdf::fibre_params;
use crate::pathtrace::integrator::MAX_DEPTH;
use crate::pathtrace::light::Light;
use crate::scene::{Mesh, Scene, Strands};
use crate::settings::Settings;

/// The linearcurve file of `strands` at `width` (one-point strands, bare roots, have no segment and are left out).
fn curves(strands: &Strands, width: f32) -> String {
    let mut out = String::new();
    for (first, count) in strands.ranges() {
        if count < 2 {
            continue;
        }
        for i in first..first + count {
            let p = strands.points[i];
            let r = crate::pathtrace::fibre::radius(strands, width, i);
            let _ = writeln!(out, "{} {} {} {}", p.x, p.y, p.z, r);
        }
        out.push('\n');
    }
    out
}

/// `mesh` as Wavefront OBJ (positions and triangles).
fn obj(mesh: &Mesh) -> String {
    let mut out = String::from("# hairlab mesh\n");
    for p in &mesh.positions {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    for t in mesh.indices.chunks_exact(3) {
        let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    out
}

fn rgb(v: glam::Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}

/// The scene XML for `scene` under `settings` (`render.width`, `render.height`, `render.spp`).
fn scene_xml(settings: &Settings, scene: &Scene, meshes: &[String]) -> Result<String> {
    let light = super::light(settings, &scene.bounds());
    let camera = super::camera(settings, scene);
    let fibre = fibre_params(settings.render.hair_color);
    let r = &settings.render;
    let (eye, target) = (camera.eye(), glam::Vec3::from(camera.target));
    let near = (0.01 * (eye - target).length()).max(1e-5);
    let mut x = String::new();
    let _ = writeln!(
        x,
        "<!-- hairlab {}: exported by `hairlab export --format mitsuba` -->",
        env!("CARGO_PKG_VERSION")
    );
    x.push_str("<scene version=\"3.0.0\">\n");
    let _ = writeln!(
        x,
        "  <integrator type=\"path\">\n    <integer name=\"max_depth\" value=\"{}\"/>\n  </integrator>",
        MAX_DEPTH + 1
    );
    let _ = writeln!(
        x,
        "  <sensor type=\"perspective\">\n    <string name=\"fov_axis\" value=\"y\"/>\n    <float name=\"fov\" value=\"{}\"/>\n    <float name=\"near_clip\" value=\"{near}\"/>\n    <transform name=\"to_world\">\n      <lookat origin=\"{}\" target=\"{}\" up=\"0, 1, 0\"/>\n    </transform>\n    <sampler type=\"independent\">\n      <integer name=\"sample_count\" value=\"{}\"/>\n      <integer name=\"seed\" value=\"{}\"/>\n    </sampler>\n    <film type=\"hdrfilm\">\n      <integer name=\"width\" value=\"{}\"/>\n      <integer name=\"height\" value=\"{}\"/>\n      <string name=\"pixel_format\" value=\"rgb\"/>\n      <rfilter type=\"box\"/>\n    </film>\n  </sensor>",
        camera.fov_y_deg,
        rgb(eye),
        rgb(target),
        r.spp,
        r.seed,
        r.width,
        r.height
    );
    match light {
        Light::Directional(d) => {
            let _ = writeln!(
                x,
                "  <emitter type=\"directional\">\n    <vector name=\"direction\" value=\"{}\"/>\n    <rgb name=\"irradiance\" value=\"{}\"/>\n  </emitter>",
                rgb(-d.to_light),
                rgb(d.irradiance)
            );
        }
        Light::Spot(s) => {
            let _ = writeln!(
                x,
                "  <emitter type=\"spot\">\n    <transform name=\"to_world\">\n      <lookat origin=\"{}\" target=\"{}\" up=\"{}\"/>\n    </transform>\n    <rgb name=\"intensity\" value=\"{}\"/>\n    <float name=\"cutoff_angle\" value=\"{}\"/>\n    <float name=\"beam_width\" value=\"{}\"/>\n  </emitter>",
                rgb(s.position),
                rgb(s.position + s.axis),
                rgb(if s.axis.y.abs() > 0.99 {
                    glam::Vec3::Z
                } else {
                    glam::Vec3::Y
                }),
                rgb(s.intensity),
                s.cutoff.to_degrees(),
                s.beam.to_degrees()
            );
        }
    }
    let _ = writeln!(
        x,
        "  <shape type=\"linearcurve\">\n    <string name=\"filename\" value=\"hair.txt\"/>\n    <bsdf type=\"hair\">\n      <rgb name=\"sigma_a\" value=\"{}\"/>\n      <float name=\"longitudinal_roughness\" value=\"{}\"/>\n      <float name=\"azimuthal_roughness\" value=\"{}\"/>\n      <float name=\"scale_tilt\" value=\"{}\"/>\n      <float name=\"int_ior\" value=\"{}\"/>\n      <float name=\"ext_ior\" value=\"1\"/>\n    </bsdf>\n  </shape>",
        rgb(fibre.sigma_a),
        fibre.beta_m,
        fibre.beta_n,
        fibre.alpha.to_degrees(),
        fibre.eta
    );
    for (file, mesh) in meshes.iter().zip(&scene.meshes) {
        let _ = writeln!(
            x,
            "  <shape type=\"obj\">\n    <string name=\"filename\" value=\"{file}\"/>\n    <boolean name=\"face_normals\" value=\"true\"/>\n    <bsdf type=\"twosided\">\n      <bsdf type=\"diffuse\">\n        <rgb name=\"reflectance\" value=\"{}\"/>\n      </bsdf>\n    </bsdf>\n  </shape>",
            rgb(mesh.color)
        );
    }
    x.push_str("</scene>\n");
    Ok(x)
}

/// Writes the Mitsuba 3 scene of `scene` under `settings` into the folder `dir` (created if missing): each file
/// whole or not at all, `scene.xml` last. Returns the files written.
pub fn export(settings: &Settings, scene: &Scene, dir: &Path) -> Result<Vec<PathBuf>> {
    if scene.strands.segment_count() == 0 {
        anyhow::bail!("the scene has no strand with two or more points: Mitsuba's linearcurve needs one");
    }
    super::check_width(settings, scene)?;
    let names: Vec<String> = (0..scene.meshes.len()).map(|k| format!("mesh{k}.obj")).collect();
    let xml = scene_xml(settings, scene, &names)?;
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow::anyhow!("{}: cannot create the folder: {e}", dir.display()))?;
    let mut files = vec![(
        dir.join("hair.txt"),
        curves(&scene.strands, settings.render.strand_width),
    )];
    files.extend(
        names
            .iter()
            .zip(&scene.meshes)
            .map(|(n, m)| (dir.join(n), obj(m))),
    );
    files.push((dir.join("scene.xml"), xml));
    for (path, text) in &files {
        crate::io::write_atomic(path, text.as_bytes())?;
    }
    Ok(files.into_iter().map(|(p, _)| p).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn curves_list_each_strand_of_two_or_more_points_then_a_blank_line() {
        let strands = Strands {
            points: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE],
            counts: vec![2, 1, 2],
            thickness: Some(vec![1.0, 0.5, 1.0, 2.0, 2.0]),
            ..Strands::default()
        };
        assert_eq!(
            curves(&strands, 0.2),
            "0 0 0 0.1\n1 0 0 0.05\n\n0 0 1 0.2\n1 1 1 0.2\n\n"
        );
    }
}
