//! The central viewport: renders the scene into the renderer's colour texture at the panel's pixel size, shows it
//! as an egui image, and turns mouse input into camera and light motion.
//!
//! Left drag orbits, middle drag (or shift + left) pans, right drag moves the light, the wheel zooms; a click
//! picks the strand under the cursor for the texel inspector.

use super::HairlabApp;
use super::inspector::SceneTexel;
use crate::methods::registry;
use crate::render::FrameInput;
use crate::render::render_settings::RenderMode;
use crate::scene::pick::{light_texel, mesh_depth, pick_segment, to_pixels};
use glam::Vec2;
use std::time::Instant;

/// How far (in points) from a strand a click may land and still pick it.
const PICK_RADIUS: f32 = 4.0;

impl HairlabApp {
    pub(super) fn viewport(&mut self, ui: &mut egui::Ui) {
        let rect = ui.available_rect_before_wrap();
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        self.camera_input(ui, &response);
        let ppp = ui.ctx().pixels_per_point();
        let width = ((rect.width() * ppp).round() as u32).clamp(1, 8192);
        let height = ((rect.height() * ppp).round() as u32).clamp(1, 8192);
        self.viewport_click(&response, width, height, ppp);
        let Some(rs) = self.render_state.clone() else {
            ui.painter().text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "no wgpu renderer",
                egui::FontId::proportional(16.0),
                ui.visuals().error_fg_color,
            );
            return;
        };
        if self.renderer.is_none() {
            // The first scene may still be building (its progress bar is below).
            let (text, color) = if self.scene_job.is_some() {
                (
                    "building the scene — see its progress below",
                    ui.visuals().text_color(),
                )
            } else {
                (
                    "no scene loaded — see the message below",
                    ui.visuals().error_fg_color,
                )
            };
            ui.painter().text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                text,
                egui::FontId::proportional(16.0),
                color,
            );
            return;
        }
        self.sync_fur();
        let Some(renderer) = self.renderer.as_mut() else {
            return;
        };
        let key = (self.settings.clone(), width, height);
        if self.probe_baking {
            if renderer.probe_pending() {
                ui.ctx()
                    .request_repaint_after(std::time::Duration::from_millis(200));
            } else {
                // The probe the last frame asked for is kept now: draw it.
                self.last_rendered = None;
            }
        }
        if self.continuous || self.last_rendered.as_ref() != Some(&key) {
            let method = match registry::find(&self.settings.method.name) {
                Ok(m) => m,
                Err(e) => {
                    self.error(e.to_string());
                    self.settings.method = Default::default();
                    return;
                }
            };
            let technique = match self.settings.transparency.technique() {
                Ok(t) => t,
                Err(e) => {
                    self.error(format!("{e:#}"));
                    self.settings.transparency = Default::default();
                    return;
                }
            };
            let start = Instant::now();
            let input = FrameInput {
                camera: &self.settings.camera,
                light: &self.settings.light,
                render: &self.settings.render,
                method,
                method_params: &self.settings.method.params,
                technique,
                technique_params: &self.settings.transparency.params,
                width,
                height,
            };
            let result = renderer.render(&input);
            self.last_rendered = Some(key);
            self.probe_baking = renderer.probe_pending();
            if let Err(e) = result {
                let msg = format!("render failed: {e}");
                self.viewport_error = Some(msg.clone());
                self.error(msg);
            } else {
                self.viewport_error = None;
            }
            let now = Instant::now();
            let ms = match (self.continuous, self.last_frame) {
                (true, Some(prev)) => (now - prev).as_secs_f64() * 1e3,
                _ => (now - start).as_secs_f64() * 1e3,
            };
            self.last_frame = Some(now);
            self.frame_ms.push_back(ms);
            while self.frame_ms.len() > 60 {
                self.frame_ms.pop_front();
            }
            // Timings arrive a frame or two later: look again shortly.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        }
        let Some(renderer) = self.renderer.as_mut() else {
            return;
        };
        if let Some(e) = &self.viewport_error {
            // Never show a stale or half-made image: say what failed instead.
            ui.painter().text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                e,
                egui::FontId::proportional(15.0),
                ui.visuals().error_fg_color,
            );
            return;
        }
        let times = renderer.timings();
        if !times.is_empty() {
            self.pass_times = times;
        }
        let generation = renderer.targets_generation();
        let id = match self.texture {
            Some((id, g)) if g == generation => id,
            Some((id, _)) => {
                rs.renderer.write().update_egui_texture_from_wgpu_texture(
                    &rs.device,
                    renderer.display_view(),
                    wgpu::FilterMode::Nearest,
                    id,
                );
                self.texture = Some((id, generation));
                id
            }
            None => {
                let id = rs.renderer.write().register_native_texture(
                    &rs.device,
                    renderer.display_view(),
                    wgpu::FilterMode::Nearest,
                );
                self.texture = Some((id, generation));
                id
            }
        };
        let path_mode = self.settings.render.mode == RenderMode::Path;
        if path_mode {
            let (scene, timeline) = (&self.scene, &self.timeline);
            let around = self
                .renderer
                .as_ref()
                .map(|r| r.light_around(self.settings.light.fit));
            self.path_view.sync(
                &self.settings,
                timeline.frame(),
                (width, height),
                || {
                    let scene = scene.as_ref()?;
                    let posed = match timeline.mesh_pose() {
                        Some((meshes, pose)) => scene.posed(&meshes, pose),
                        None => Ok(scene.clone()),
                    };
                    Some(posed.map(|s| {
                        let around = around.unwrap_or_else(|| s.bounds());
                        (s, around)
                    }))
                },
                ui.ctx(),
                self.job_gate.clone(),
            );
        } else if self.path_view.active() {
            self.path_view.clear();
        }
        if !(path_mode && self.path_view.update(ui.ctx())) {
            ui.painter().image(
                id,
                rect,
                egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                egui::Color32::WHITE,
            );
        }
        if path_mode {
            self.path_view.paint(ui, rect);
        }
        self.paint_pick(ui.painter(), rect, width, height);
    }

    /// Viewport input: a click without drag picks the strand under the cursor and inspects its light texel.
    fn viewport_click(&mut self, response: &egui::Response, width: u32, height: u32, ppp: f32) {
        self.viewport_rect = Some(response.rect);
        if !response.clicked() {
            return;
        }
        let Some(pos) = response.interact_pointer_pos() else {
            return;
        };
        let (Some(r), Some(scene)) = (&self.renderer, &self.scene) else {
            return;
        };
        let m = r.world_to_clip(&self.settings.camera, width, height);
        let size = Vec2::new(width as f32, height as f32);
        let cursor = Vec2::new(pos.x - response.rect.min.x, pos.y - response.rect.min.y) * ppp;
        let limit = mesh_depth(&scene.meshes, m, size, cursor);
        let Some(pick) = pick_segment(&scene.strands, m, size, cursor, PICK_RADIUS * ppp, limit) else {
            if self.inspector.open {
                self.info("no strand under the cursor");
            }
            return;
        };
        let frame = r.hair_light_frame(&self.settings.light);
        let resolution = self.settings.render.light_map_side();
        let Some(texel) = light_texel(frame.world_to_clip(), resolution, pick.world) else {
            return self.error("the picked point lies outside the light map");
        };
        let depth = frame.depth(pick.world);
        self.inspector.select(SceneTexel {
            texel,
            picked: Some(pick),
        });
        self.refresh_lists(true);
        let texel = match self.inspector.current_lists(&self.lists_key()) {
            Some(l) => l.resolve_pick(texel, pick.segment, depth),
            None => texel,
        };
        self.inspector.select(SceneTexel {
            texel,
            picked: Some(pick),
        });
        self.info(format!(
            "picked segment {} at light depth {depth:.4}: texel ({}, {})",
            pick.segment, texel[0], texel[1]
        ));
    }

    /// Marks the picked point in the viewport while its texel is inspected.
    fn paint_pick(&self, painter: &egui::Painter, rect: egui::Rect, width: u32, height: u32) {
        let (Some(p), Some(r)) = (self.inspector.shown_pick(), &self.renderer) else {
            return;
        };
        let c = r.world_to_clip(&self.settings.camera, width, height) * p.world.extend(1.0);
        if c.w <= 0.0 {
            return;
        }
        let (px, _) = to_pixels(c, Vec2::new(rect.width(), rect.height()));
        let at = rect.min + egui::vec2(px.x, px.y);
        painter.circle_stroke(at, 7.0, egui::Stroke::new(2.0, egui::Color32::YELLOW));
        painter.circle_filled(at, 1.5, egui::Color32::YELLOW);
    }

    fn camera_input(&mut self, ui: &egui::Ui, response: &egui::Response) {
        let cam = &mut self.settings.camera;
        let delta = response.drag_delta();
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(egui::PointerButton::Primary) && !shift {
            cam.yaw_deg = (cam.yaw_deg - delta.x * 0.4).rem_euclid(360.0);
            cam.pitch_deg = (cam.pitch_deg + delta.y * 0.4).clamp(-89.0, 89.0);
        }
        if response.dragged_by(egui::PointerButton::Middle)
            || (response.dragged_by(egui::PointerButton::Primary) && shift)
        {
            let view = cam.world_to_view().inverse();
            let scale = cam.distance * (cam.fov_y_deg.to_radians() * 0.5).tan() * 2.0
                / response.rect.height().max(1.0);
            let right = view.x_axis.truncate() * (-delta.x * scale);
            let up = view.y_axis.truncate() * (delta.y * scale);
            let t = glam::Vec3::from(cam.target) + right + up;
            cam.target = t.into();
        }
        if response.dragged_by(egui::PointerButton::Secondary) {
            let l = &mut self.settings.light;
            l.azimuth_deg = (l.azimuth_deg + delta.x * 0.4).rem_euclid(360.0);
            l.elevation_deg = (l.elevation_deg - delta.y * 0.4).clamp(-89.0, 89.0);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                cam.distance = (cam.distance * (-scroll * 0.002).exp()).max(1e-4);
            }
        }
    }
}
