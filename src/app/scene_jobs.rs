//! The window's long work polled from its frame loop: the scene build, the motion bound, the whole-map
//! statistics and a method's analysis, each a job (`jobs.rs`) applied when it is done.

use super::*;
use crate::progress::Progress as _;

impl HairlabApp {
    /// Starts building the scene from the settings (generator or file) on a worker thread, replacing a build
    /// under way for other settings, and applies it when it is done within [`PATIENCE`] (later frames apply it
    /// otherwise). Until then the window shows the previous scene.
    pub(super) fn rebuild_scene(&mut self) {
        let (scene, motion) = (self.settings.scene.clone(), self.settings.motion.clone());
        if self
            .scene_job
            .as_ref()
            .is_some_and(|j| j.scene == scene && j.motion == motion)
        {
            return;
        }
        let settings = self.settings.clone();
        let what = if scene.file.is_some() {
            "loading the strands"
        } else {
            "growing the strands"
        };
        let job = Job::spawn("scene", &self.egui_ctx, self.job_gate.clone(), move |ctl| {
            let start = Instant::now();
            if !ctl.step(what, 0.0) {
                return None;
            }
            let built = settings.open_motion_with(&mut ctl.clone().part(0.0, 0.9));
            // A stopped build's partial scene (or its error) is dropped.
            ctl.step("preparing the motion", 0.95).then_some(())?;
            let ms = start.elapsed().as_secs_f64() * 1e3;
            Some(built.map(|(s, m)| (s, m, ms)).map_err(|e| format!("{e:#}")))
        });
        self.scene_job = Some(SceneJob { job, scene, motion });
        self.poll_scene_job(PATIENCE);
    }

    /// Applies the scene job's result when it is done (waiting up to `patience`); a cancelled job leaves the
    /// previous scene and puts back the settings it was built with.
    pub(super) fn poll_scene_job(&mut self, patience: Duration) {
        let Some(j) = &self.scene_job else { return };
        match j.job.wait(patience) {
            Poll::Running => {}
            Poll::Done(result) => {
                let Some(j) = self.scene_job.take() else { return };
                match result {
                    Ok((scene, motion, ms)) => self.apply_scene(scene, motion, ms, j.scene, &j.motion),
                    Err(e) => {
                        self.error(e);
                        self.restore_built_scene();
                    }
                }
            }
            Poll::Gone => {
                let cancelled = j.job.cancelled();
                let what = j
                    .scene
                    .file
                    .as_ref()
                    .map_or_else(|| "the generated scene".to_string(), |f| f.display().to_string());
                self.scene_job = None;
                self.restore_built_scene();
                if cancelled {
                    self.info("scene: cancelled; the previous scene stays");
                } else {
                    self.error(format!(
                        "{what}: reading it stopped without a result (a bug in a reader); the previous scene stays"
                    ));
                }
            }
        }
    }

    /// Puts back the scene and motion settings of the scene on screen (when there is one).
    pub(super) fn restore_built_scene(&mut self) {
        if let Some(prev) = self.built_scene.clone() {
            self.settings.scene = prev;
            if let Some(m) = self.timeline.opened_with() {
                self.settings.motion = m.clone();
            }
        }
    }

    /// Uploads a built scene and makes it the one on screen; on failure the previous scene stays.
    pub(super) fn apply_scene(
        &mut self,
        scene: Scene,
        motion: crate::motion::Motion,
        ms: f64,
        scene_settings: SceneSettings,
        motion_settings: &crate::motion::MotionSettings,
    ) {
        self.scene_ms = ms;
        if self.settings.camera.distance <= 0.0
            || self
                .built_scene
                .as_ref()
                .is_some_and(|b| b.file != scene_settings.file)
        {
            self.settings.camera.frame(&scene.framing_bounds());
        }
        let Some(gpu) = window_gpu(self.render_state.as_ref()) else {
            self.scene = Some(scene);
            self.built_scene = Some(scene_settings);
            self.timeline.set_motion(motion, motion_settings);
            return;
        };
        let result = match self.renderer.as_mut() {
            Some(r) => r.set_scene(&scene),
            None => Renderer::new(&gpu, &scene, self.settings.render.map_resolution).map(|mut r| {
                // The window does not stop for the path tracer's probe: it bakes on another thread.
                r.set_background_probes(true);
                self.renderer = Some(r);
            }),
        };
        match result {
            Ok(()) => {
                let counts = format!(
                    "scene: {} strands, {} segments, {} triangles",
                    scene.strands.strand_count(),
                    scene.strands.segment_count(),
                    scene.triangle_count()
                );
                // A layer the file brings in that is missing or unreadable is said, not just logged.
                match scene.warnings.first() {
                    None => self.info(counts),
                    Some(first) => self.error(format!(
                        "{counts}; {} warning(s), the first: {first}",
                        scene.warnings.len()
                    )),
                }
                self.scene = Some(scene);
                self.built_scene = Some(scene_settings);
                self.timeline.set_motion(motion, motion_settings);
                self.motion_bound.scene_uploaded();
                self.last_rendered = None;
                // The fur grows on the new scene's mesh.
                self.built_fur = None;
                self.fur = None;
            }
            Err(e) => {
                self.error(format!("cannot upload the scene: {e}"));
                self.restore_built_scene();
            }
        }
    }

    /// Makes jobs started from now on wait at each of their steps until the returned gate opens: a test hook
    /// that holds a job at a point the test chooses.
    pub fn hold_jobs(&mut self) -> JobGate {
        let gate = JobGate::default();
        self.job_gate = Some(gate.clone());
        gate
    }

    /// Every job under way (scene, analysis, the inspector's, compare, time view, animation export, bench,
    /// report export), as the progress bar shows them.
    pub fn jobs(&self) -> Vec<JobStatus> {
        let mut all: Vec<JobStatus> = self.scene_job.iter().map(|j| j.job.status()).collect();
        all.extend(self.analysis_job.iter().map(|j| j.job.status()));
        all.extend(self.inspector.job_status());
        all.extend(self.motion_bound.status());
        all.extend(self.compare.job_status());
        all.extend(self.compare.truth.job_status());
        all.extend(self.time_view.job_status());
        all.extend(self.animation_export.job_status());
        all.extend(self.bench_status());
        all.extend(self.bench.report.iter().map(|(job, _)| job.status()));
        all
    }

    /// Waits for the scene, analysis, inspector and compare jobs under way and applies their results (for
    /// scripts and tests that need a finished state).
    pub fn finish_jobs(&mut self) {
        const FOREVER: Duration = Duration::from_secs(24 * 3600);
        self.poll_scene_job(FOREVER);
        self.poll_analysis_job(FOREVER);
        self.poll_inspector_jobs(FOREVER);
        self.fit_motion_bound(FOREVER);
        self.poll_compare(FOREVER);
        self.path_view.wait(FOREVER);
    }

    /// Takes the results of the jobs that finished (waiting up to `patience` for each).
    pub(super) fn poll_jobs(&mut self, patience: Duration) {
        self.poll_scene_job(patience);
        self.poll_analysis_job(patience);
        self.poll_inspector_jobs(patience);
        self.fit_motion_bound(patience);
        self.poll_compare(patience);
    }

    /// Keeps the renderer's fit bound the whole motion's box while `light.fit` is `bound` or `stable` and the
    /// scene moves (`motion_bound.rs`; the box is found on a worker).
    pub(super) fn fit_motion_bound(&mut self, patience: Duration) {
        let wanted = (self.settings.light.fit != crate::scene::LightFit::PerFrame)
            .then(|| Some((self.built_scene.clone()?, self.timeline.opened_with()?.clone())))
            .flatten()
            .filter(|_| self.timeline.is_moving());
        let apply = self.motion_bound.update(
            wanted,
            &self.settings,
            &self.egui_ctx,
            self.job_gate.clone(),
            patience,
        );
        let bound = match apply {
            motion_bound::Apply::Nothing => return,
            motion_bound::Apply::Failed(e) => return self.error(e),
            motion_bound::Apply::Bound(b) => Some(b),
            motion_bound::Apply::Clear => None,
        };
        if let Some(r) = self.renderer.as_mut() {
            r.set_fit_bound(bound);
            self.last_rendered = None;
        }
    }

    /// Starts the whole-map statistics job of the inspector and gives it [`PATIENCE`] to finish.
    pub(super) fn start_map_stats(&mut self, ctx: &egui::Context) {
        if self.inspector.compute_map_stats(ctx, self.job_gate.clone()) {
            self.poll_inspector_jobs(PATIENCE);
        }
    }

    /// Starts the inspector's `α` fit to the ray-traced fibres (a job on the window's GPU) and gives it
    /// [`PATIENCE`] to finish.
    pub(super) fn start_alpha_fit(&mut self, ctx: &egui::Context) {
        let Some(gpu) = window_gpu(self.render_state.as_ref()) else {
            return self.error("α fit: no GPU renderer");
        };
        self.inspector
            .start_alpha_fit(gpu, &self.settings, ctx, self.job_gate.clone());
        self.poll_inspector_jobs(PATIENCE);
    }

    /// Takes the inspector's finished jobs (whole-map statistics, ray-traced texels, `α` fit), waiting up to
    /// `patience` for each.
    pub(super) fn poll_inspector_jobs(&mut self, patience: Duration) {
        if let Some(m) = self.inspector.poll_map_stats(patience) {
            self.info(m);
        }
        self.inspector.poll_traced(patience);
        match self.inspector.poll_alpha_fit(patience) {
            Some(Ok(m)) => self.info(m),
            Some(Err(e)) => self.error(e),
            None => {}
        }
    }

    /// Reads the exact fragment lists of the current light view and runs a method's on-demand analysis on
    /// them as a job; the parameters it picks are applied when it is done.
    pub(super) fn run_analysis(
        &mut self,
        method: &'static dyn crate::methods::ShadowMethod,
        a: crate::methods::Analysis,
    ) {
        let Some(r) = self.renderer.as_mut() else { return };
        match inspector::read_reference_lists(r, &self.settings) {
            Ok(lists) => {
                let (params, run) = (self.settings.method.params.clone(), a.run);
                let job = Job::spawn(a.label, &self.egui_ctx, self.job_gate.clone(), move |ctl| {
                    ctl.step("analysing the fragment lists", 0.0).then_some(())?;
                    Some(run(&lists, &params))
                });
                self.analysis_job = Some(AnalysisJob {
                    method: method.name(),
                    label: a.label,
                    job,
                });
                self.poll_analysis_job(PATIENCE);
            }
            Err(e) => self.error(format!("{}: {e}", a.label)),
        }
    }

    /// Applies the analysis job's parameters when it is done (waiting up to `patience`) and the method is still
    /// the one it analysed.
    pub(super) fn poll_analysis_job(&mut self, patience: Duration) {
        let Some(j) = &self.analysis_job else { return };
        match j.job.wait(patience) {
            Poll::Running => {}
            Poll::Done(result) => {
                let (method, label) = (j.method, j.label);
                self.analysis_job = None;
                if self.settings.method.name != method {
                    self.info(format!(
                        "{label}: the method changed meanwhile; its result is dropped"
                    ));
                    return;
                }
                self.settings.method.params.extend(result.apply.clone());
                self.info(format!("{label}: {}", result.summary));
                self.analysis = Some((method, result));
            }
            Poll::Gone => {
                let label = j.label;
                self.analysis_job = None;
                self.info(format!("{label}: cancelled"));
            }
        }
    }
}
