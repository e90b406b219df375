//! The window's floating windows: the transparency compare view, the time view, the animation export and the
//! texel inspector with its curves.

use super::*;

impl HairlabApp {
    /// The compare window (renders when asked or, in auto mode, when the settings changed and no drag is under
    /// way) and the pixel inspector window.
    pub(super) fn transparency_windows(&mut self, ctx: &egui::Context) {
        if self.compare.open {
            let area = self.viewport_rect.unwrap_or_else(|| ctx.content_rect());
            let size = self.compare.size(&self.settings.render);
            if self.compare.auto && self.settled && self.compare.stale(&self.settings, size) {
                self.render_compare(size, ctx);
            }
            let mut open = self.compare.open;
            let (settings, hide) = (&self.settings, self.snapshot_mode);
            let action = egui::Window::new("Compare")
                .open(&mut open)
                .default_pos([area.left() + 8.0, area.top() + 8.0])
                .default_size([
                    (area.width() - 16.0).max(400.0),
                    (area.height() - 16.0).max(400.0),
                ])
                .show(ctx, |ui| {
                    egui::ScrollArea::vertical()
                        .show(ui, |ui| self.compare.ui(ui, settings, hide))
                        .inner
                })
                .and_then(|r| r.inner)
                .flatten();
            self.compare.open = open;
            match action {
                Some(compare_view::CompareAction::Render) => self.render_compare(size, ctx),
                Some(compare_view::CompareAction::Pick(p)) => self.pixel_inspector.select(p),
                Some(compare_view::CompareAction::Export) => {
                    self.request_export(exports::Export::Compare, ctx)
                }
                Some(compare_view::CompareAction::Decompose) => self.decompose_truth(ctx),
                None => {}
            }
        }
        if self.pixel_inspector.open {
            let mut open = self.pixel_inspector.open;
            let (frames, generation) = (self.compare.frames(), self.compare.generation());
            let truth = self.compare.truth.result();
            egui::Window::new("Pixel inspector")
                .open(&mut open)
                .default_size([560.0, 520.0])
                .show(ctx, |ui| self.pixel_inspector.ui(ui, frames, generation, truth));
            self.pixel_inspector.open = open;
            if self.pixel_inspector.take_export() {
                self.request_export(exports::Export::Pixel, ctx);
            }
        }
    }

    /// Starts the compare render (a job with a renderer of its own) and gives it [`PATIENCE`] to finish.
    pub(super) fn render_compare(&mut self, size: (u32, u32), ctx: &egui::Context) {
        let gpu = window_gpu(self.render_state.as_ref());
        let (Some(gpu), Some(scene), Some(_)) = (gpu, &self.scene, &self.renderer) else {
            return self.error("compare view: no GPU renderer");
        };
        let source = compare_view::CompareSource {
            gpu,
            scene: scene.clone(),
            fur: self.fur.clone(),
            fit_bound: self
                .renderer
                .as_ref()
                .map(|r| r.fit_box(crate::scene::LightFit::Bound)),
            mesh_pose: self.timeline.mesh_pose(),
        };
        self.compare
            .start(source, &self.settings, size, ctx, self.job_gate.clone());
        self.poll_compare(PATIENCE);
    }

    /// Starts decomposing the selected method's error against the path-traced truth (a job on a clone of the
    /// window's GPU) and gives it [`PATIENCE`] to finish.
    pub(super) fn decompose_truth(&mut self, ctx: &egui::Context) {
        let Some(gpu) = window_gpu(self.render_state.as_ref()) else {
            return self.error("truth: no GPU");
        };
        self.compare
            .truth
            .start(gpu, &self.settings, ctx, self.job_gate.clone());
        self.poll_compare(PATIENCE);
    }

    /// Applies the compare render's and the decomposition's outcomes when they are done (waiting up to
    /// `patience` for each).
    pub(super) fn poll_compare(&mut self, patience: Duration) {
        let render = self.compare.poll(patience, &self.egui_ctx);
        let truth = self.compare.truth.poll(patience);
        for polled in [render, truth].into_iter().flatten() {
            match polled {
                Ok(m) => self.info(m),
                Err(e) => self.error(e),
            }
        }
    }

    /// Opens the time view on the hair point picked for the texel inspector and measures it.
    pub(super) fn open_time_view(&mut self, ctx: &egui::Context) {
        let (Some(pick), Some(scene)) = (self.inspector.shown_pick(), &self.scene) else {
            return self.error("time view: pick a hair point in the viewport first");
        };
        if !self.timeline.is_moving() {
            return self
                .error("time view: the scene has no motion (try the wind, head-turn or stray-sweep preset)");
        }
        let point = FollowedPoint::on_segment(&scene.strands.points, pick.segment, pick.world);
        self.time_view
            .follow(point, &scene.strands, self.timeline.frame_count());
        self.start_time_view(ctx);
    }

    pub(super) fn start_time_view(&mut self, ctx: &egui::Context) {
        let Some(gpu) = window_gpu(self.render_state.as_ref()) else {
            return self.error("time view: no GPU renderer");
        };
        self.time_view
            .start(gpu, &self.settings, ctx, self.job_gate.clone());
    }

    /// The time view's window while it is open (its measurement is a job).
    pub(super) fn time_view_window(&mut self, ctx: &egui::Context) {
        self.time_view.poll();
        if !self.time_view.open {
            return;
        }
        let mut open = true;
        let (frame, count) = (self.timeline.frame(), self.timeline.frame_count());
        let area = self.viewport_rect.unwrap_or_else(|| ctx.content_rect());
        let action = egui::Window::new("Time view")
            .open(&mut open)
            .default_pos([area.left() + 8.0, area.top() + 8.0])
            .default_size([(area.width() - 16.0).clamp(400.0, 760.0), 520.0])
            .show(ctx, |ui| self.time_view.ui(ui, frame, count))
            .and_then(|r| r.inner)
            .flatten();
        if !open {
            self.time_view.cancel();
        }
        self.time_view.open = open;
        match action {
            Some(time_view::TimeViewAction::Run) => self.start_time_view(ctx),
            Some(time_view::TimeViewAction::Seek(k)) => self.timeline.seek(k),
            None => {}
        }
    }

    /// The animation export window while it is open (its frames render in a job).
    pub(super) fn animation_export_window(&mut self, ctx: &egui::Context) {
        self.animation_export.poll();
        if !self.animation_export.open {
            return;
        }
        let mut open = true;
        let count = self.timeline.frame_count();
        let (settings, rs, gate) = (&self.settings, &self.render_state, self.job_gate.clone());
        let gpu = || window_gpu(rs.as_ref());
        let export = &mut self.animation_export;
        egui::Window::new("Export animation")
            .open(&mut open)
            .show(ctx, |ui| export.ui(ui, count, settings, gpu, gate));
        if !open {
            self.animation_export.cancel();
        }
        self.animation_export.open = open;
    }

    /// The animation export (for tests and scripts).
    pub fn animation_export_mut(&mut self) -> &mut export_animation::AnimationExport {
        &mut self.animation_export
    }

    /// The time view (for tests and scripts).
    pub fn time_view(&self) -> &time_view::TimeView {
        &self.time_view
    }

    /// Writes every curve shown (see [`inspector::TexelCurves::csv`]) to `path`; the outcome goes to the status
    /// line.
    pub fn export_inspector_csv(&mut self, path: &std::path::Path) {
        self.refresh_lists(true);
        self.update_curves();
        match inspector::export(self.inspector.curves(), path) {
            Ok(m) => self.info(m),
            Err(e) => self.error(e),
        }
    }

    /// The key of the reference lists the current settings need.
    pub(super) fn lists_key(&self) -> ListsKey {
        ListsKey::new(
            &self.settings,
            self.renderer.as_ref().map(Renderer::scene_generation),
        )
    }

    /// Reads the reference lists again when a window needs them and what they depend on changed (and `allow`,
    /// i.e. no drag is under way); a failed read is reported once and not retried until something changes.
    pub(super) fn refresh_lists(&mut self, allow: bool) {
        if !(self.inspector.needs_lists() || self.light_map.open) {
            return;
        }
        let key = self.lists_key();
        let (renderer, settings) = (&mut self.renderer, &self.settings);
        let read = || {
            let r = renderer
                .as_mut()
                .ok_or("no GPU renderer: only the synthetic texel lab works")?;
            inspector::read_reference_lists(r, settings)
        };
        match self.inspector.refresh_lists(key, allow, read) {
            // The light pass replaced the frame's timings: render the viewport again to show its own.
            Some(Ok(())) => self.last_rendered = None,
            Some(Err(e)) => self.error(format!("texel inspector: {e}")),
            None => {}
        }
    }

    /// Recomputes the inspector's curves when their inputs changed (tracing the fibres of its texels first, a
    /// job); reports a new error in the lab's text.
    pub(super) fn update_curves(&mut self) {
        let fibres = match (&self.scene, &self.renderer) {
            (Some(s), Some(r)) => Some(inspector::FibreScene {
                strands: &s.strands,
                generation: r.scene_generation(),
                frame: r.hair_light_frame(&self.settings.light),
            }),
            _ => None,
        };
        let gate = self.job_gate.clone();
        self.inspector
            .update_traced(fibres, &self.settings, self.settled, &self.egui_ctx, gate);
        if let Some(e) = self.inspector.update_curves(&self.settings) {
            self.error(e);
        }
    }

    /// The inspector and light-map windows (each frame; they do nothing while closed).
    pub(super) fn inspector_windows(&mut self, ctx: &egui::Context) {
        if !(self.inspector.open || self.light_map.open) {
            return;
        }
        self.refresh_lists(self.settled);
        self.update_curves();
        // First placement: the inspector along the bottom of the viewport, the light map in its top right corner,
        // so that the hair stays in view for picking.
        let area = self.viewport_rect.unwrap_or_else(|| ctx.content_rect());
        let width = (area.width() - 16.0).clamp(300.0, 900.0);
        let mut open = self.inspector.open;
        let deps = InspectorDeps {
            settings: &self.settings,
            light_map_open: self.light_map.open,
        };
        let action = egui::Window::new("Texel inspector")
            .open(&mut open)
            .default_pos([area.left() + 8.0, (area.bottom() - 440.0).max(area.top())])
            .default_size([width, 400.0])
            .show(ctx, |ui| self.inspector.ui(ui, deps))
            .and_then(|r| r.inner)
            .flatten();
        self.inspector.open = open;
        match action {
            Some(InspectorAction::ExportCsv) => self.open_dialog(DialogPurpose::ExportCurves, ctx),
            Some(InspectorAction::ExportPlot) => self.request_export(exports::Export::Texel, ctx),
            Some(InspectorAction::CopyPlot) => self.copy_texel_plot(ctx),
            Some(InspectorAction::OpenLightMap) => self.light_map.open = true,
            Some(InspectorAction::TimeView) => self.open_time_view(ctx),
            Some(InspectorAction::ComputeMapStats) => self.start_map_stats(ctx),
            Some(InspectorAction::FitAlpha) => self.start_alpha_fit(ctx),
            Some(InspectorAction::ApplyFittedAlpha) => {
                if let Some(a) = self.inspector.alpha_fit(&self.settings).and_then(|f| f.alpha()) {
                    self.settings.render.hair_alpha = a;
                    self.info(format!("render.hair_alpha = {a} (the α fitted to the fibres)"));
                }
            }
            None => {}
        }
        let mut open = self.light_map.open;
        let pins = self.inspector.pinned_texels();
        let deps = LightMapDeps {
            lists: self.inspector.lists(),
            settings: &self.settings,
            selected: self.inspector.scene_texel(),
            pins: &pins,
        };
        let clicked = egui::Window::new("Light map")
            .open(&mut open)
            .default_pos([(area.right() - 350.0).max(area.left()), area.top() + 8.0])
            .default_size([340.0, (area.height() - 470.0).clamp(240.0, 420.0)])
            .show(ctx, |ui| self.light_map.ui(ui, deps))
            .and_then(|r| r.inner)
            .flatten();
        self.light_map.open = open;
        if let Some(texel) = clicked {
            self.inspector.select(SceneTexel { texel, picked: None });
        }
    }
}
