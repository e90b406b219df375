//! The per-frame scene (`SceneGpu`): moving every strand point through the one write path
//! (`Renderer::update_points`) renders the image that loading the moved strands from a `.hair` file renders,
//! for every shadow method, and re-creates nothing; the light-frame fit policy (`light.fit`); bad point counts.

use crate::common;

use glam::Vec3;
use hairlab::gpu::Gpu;
use hairlab::methods::registry;
use hairlab::path_scene::PathScene;
use hairlab::pathtrace::light::Light as PathLight;
use hairlab::render::Renderer;
use hairlab::scene::hair::{HairFile, write_hair_file};
use hairlab::scene::{Aabb, LightFit, LightKind, Scene, load::load_scene};
use hairlab::settings::Settings;

/// The default head (strands and its mesh) with the camera framed on it.
fn head() -> (Settings, Scene) {
    let mut s = common::small_settings(96, 72);
    let scene = s.scene.build().unwrap();
    s.camera.frame(&scene.framing_bounds());
    (s, scene)
}

#[test]
fn moved_points_render_like_the_moved_strands_loaded_from_a_file() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (s, scene) = head();
    assert!(
        !scene.meshes.is_empty(),
        "the head's mesh must be part of the comparison"
    );
    // Under `per-frame` (`small_settings`) the light frame follows the hair, so the moved points and the loaded
    // file get one frame (`bound` and `stable` keep the frame of the points as uploaded).
    assert_eq!(s.light.fit, LightFit::PerFrame);
    // An offset that is not a multiple of a texel or a pixel, so the light frame must follow the hair.
    let offset = Vec3::new(0.0131, -0.0207, 0.0089);
    let moved: Vec<Vec3> = scene.strands.points.iter().map(|p| *p + offset).collect();
    let mut moved_strands = scene.strands.clone();
    moved_strands.points = moved.clone();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("moved.hair");
    write_hair_file(&path, &HairFile::from_strands(&moved_strands, "moved").unwrap()).unwrap();
    let loaded = Scene::new(load_scene(&path).unwrap().strands, scene.meshes.clone());
    assert_eq!(
        loaded.strands.points, moved,
        "the file must hold the moved points exactly"
    );

    let mut live = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let mut fresh = Renderer::new(&gpu, &loaded, s.render.map_resolution).unwrap();
    let vertices = live.scene_gpu().hair_vertices.clone();
    let mut compared = 0;
    for method in registry::all() {
        let m = *method;
        live.update_points(&scene.strands.points).unwrap();
        live.render(&common::frame_input(&s, m)).unwrap();
        let unmoved = live.read_output().unwrap();
        let before = live.creations();
        let generation = live.scene_generation();
        live.update_points(&moved).unwrap();
        assert_ne!(
            live.scene_generation(),
            generation,
            "moving the points is a new generation"
        );
        live.render(&common::frame_input(&s, m)).unwrap();
        let image = live.read_output().unwrap();
        assert_eq!(
            live.creations(),
            before,
            "{}: a frame after update_points re-created GPU state",
            m.name()
        );
        assert!(
            live.scene_gpu().hair_vertices == vertices,
            "the strand vertex buffer was re-created"
        );
        fresh.render(&common::frame_input(&s, m)).unwrap();
        let expected = fresh.read_output().unwrap();
        let differing = image
            .pixels()
            .zip(expected.pixels())
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            differing,
            0,
            "{}: {differing} pixels differ from the loaded scene's",
            m.name()
        );
        let moved_pixels = image
            .pixels()
            .zip(unmoved.pixels())
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            moved_pixels > 100,
            "{}: the offset moved only {moved_pixels} pixels",
            m.name()
        );
        compared += 1;
    }
    assert_eq!(compared, registry::all().len());
    // One upload each; a method's state per method; no pipeline built twice for the same key.
    assert_eq!(live.creations().scene_uploads, 1);
    assert_eq!(live.creations().method_states, registry::all().len() as u64);
}

#[test]
fn light_fit_bound_keeps_one_frame_while_per_frame_follows_the_hair() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = head();
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    let offset = Vec3::new(0.02, 0.01, -0.015);
    let moved: Vec<Vec3> = scene.strands.points.iter().map(|p| *p + offset).collect();
    let bounds = scene.strand_bounds();
    let motion = Aabb::from_points(&[bounds.min - 0.05, bounds.max + 0.05]);

    s.light.fit = LightFit::PerFrame;
    let still = r.hair_light_frame(&s.light);
    r.update_points(&moved).unwrap();
    let followed = r.hair_light_frame(&s.light);
    assert_ne!(still, followed, "per-frame fitting follows the moved hair");
    // Fitted per frame, the moved hair sits where the still hair sat in normalised light depth.
    let (p, q) = (scene.strands.points[0], moved[0]);
    assert!((still.depth(p) - followed.depth(q)).abs() < 1e-4);

    s.light.fit = LightFit::Bound;
    r.set_fit_bound(Some(motion));
    let a = r.hair_light_frame(&s.light);
    r.update_points(&scene.strands.points).unwrap();
    let b = r.hair_light_frame(&s.light);
    assert_eq!(
        a, b,
        "a bound fit is the same frame whatever the hair's pose inside the bound"
    );
    // The bound holds both poses: every point of each maps inside [0, 1] of light depth.
    for p in scene.strands.points.iter().chain(&moved) {
        let d = a.depth(*p);
        assert!((0.0..=1.0).contains(&d), "depth {d} outside the bound's frame");
    }
}

/// One spot light and one pose: on a posed frame of a moving groom (the head turned and moved, the motion's
/// bound set), under every light fit, the hair maps' frame, the meshes' shadow map and the path tracer of the
/// posed scene place the spot at one point, and the renderer's posed meshes are the CPU's `Scene::posed`. Under
/// `bound` and `stable` the box the light is placed around is not the posed frame's bounds (the path tracer
/// placed it around those before, elsewhere by 0.03–0.3 scene units here).
#[test]
fn the_renderer_and_the_path_tracer_place_one_spot_light_under_every_fit() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (mut s, scene) = head();
    s.light.kind = LightKind::Spot;
    assert!(!scene.meshes.is_empty(), "the default head has a mesh");
    let centre = Aabb::from_points(&scene.meshes[0].positions).center();
    let turn = glam::Affine3A::from_translation(centre + Vec3::new(0.05, 0.02, 0.0))
        * glam::Affine3A::from_rotation_y(0.6)
        * glam::Affine3A::from_translation(-centre);
    let mut r = Renderer::new(&gpu, &scene, s.render.map_resolution).unwrap();
    r.pose_meshes(&[0], turn).unwrap();
    let bounds = scene.strand_bounds();
    r.set_fit_bound(Some(Aabb::from_points(&[bounds.min - 0.05, bounds.max + 0.05])));
    let posed = scene.posed(&[0], turn).unwrap();
    let drawn = r.read_mesh_positions().unwrap();
    let cpu: Vec<Vec3> = posed.meshes.iter().flat_map(|m| m.positions.clone()).collect();
    assert_eq!(drawn.len(), cpu.len());
    let worst = drawn
        .iter()
        .zip(&cpu)
        .map(|(a, b)| a.distance(*b))
        .fold(0.0, f32::max);
    assert!(worst < 1e-6, "GPU and CPU poses differ by {worst}");

    for fit in [LightFit::PerFrame, LightFit::Bound, LightFit::Stable] {
        s.light.fit = fit;
        let around = r.light_around(fit);
        let hair = r.hair_light_frame(&s.light).position;
        let shadow = r.shadow_light_frame(&s.light).position;
        let path = PathScene::placed(&s, &posed, &around).unwrap();
        let PathLight::Spot(spot) = path.light else {
            panic!("a spot light traces as a spot")
        };
        assert_eq!(hair, s.light.spot_position(&around), "{fit:?}");
        assert!(
            hair.distance(shadow) < 1e-6 && hair.distance(spot.position) < 1e-6,
            "{fit:?}: hair maps' spot {hair}, shadow map's {shadow}, path tracer's {}",
            spot.position
        );
        let apart = s.light.spot_position(&posed.bounds()).distance(hair);
        match fit {
            LightFit::PerFrame => assert!(apart < 1e-6, "per-frame: around the posed bounds"),
            _ => assert!(
                apart > 0.01,
                "{fit:?}: the posed bounds place it only {apart} away"
            ),
        }
    }
    assert_eq!(
        scene.posed(&[7], turn).unwrap_err(),
        r.pose_meshes(&[7], turn).unwrap_err().to_string(),
        "one check of the meshes a pose names"
    );
}

#[test]
fn a_point_count_that_is_not_the_scenes_is_refused() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let (_, scene) = head();
    let mut r = Renderer::new(&gpu, &scene, 64).unwrap();
    let generation = r.scene_generation();
    let n = scene.strands.points.len();
    let err = r
        .update_points(&scene.strands.points[..n - 1])
        .unwrap_err()
        .to_string();
    assert_eq!(
        err,
        format!(
            "{} new strand points for a scene of {n} points (the topology of moving hair is fixed)",
            n - 1
        )
    );
    assert_eq!(
        r.scene_generation(),
        generation,
        "a refused update changes nothing"
    );
}
