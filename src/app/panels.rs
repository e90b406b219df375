//! The side panel: scene, render, light, shadow method (generated from the method's parameter specs), presets
//! and statistics.

use super::{DialogPurpose, HairlabApp, method_names};
use crate::methods::{self, ParamKind, registry};
use crate::scene::LightKind;
use crate::scene::generate::{GenKind, HairStyle};

/// Map resolutions offered in the UI.
const MAP_RESOLUTIONS: &[u32] = &[64, 128, 256, 512, 1024, 2048];

/// One labelled grid row; the label names the widget for screen readers.
fn row(ui: &mut egui::Ui, label: &str, widget: impl egui::Widget) -> egui::Response {
    let l = ui.label(label);
    let r = ui.add(widget).labelled_by(l.id);
    ui.end_row();
    r
}

fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / (1024.0 * 1024.0))
}

impl HairlabApp {
    pub(super) fn controls(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        ui.heading("hairlab");
        ui.horizontal(|ui| {
            if ui
                .button("Export screenshot…")
                .on_hover_text("Ctrl+S; F12 saves into the working folder")
                .clicked()
            {
                self.open_dialog(DialogPurpose::SaveScreenshot, ctx);
            }
            if ui.button("Frame scene").on_hover_text("F").clicked() {
                self.frame_scene();
            }
            if ui
                .button("Bench")
                .on_hover_text("sweep every method: GPU time against map error")
                .clicked()
            {
                self.bench.open = !self.bench.open;
            }
        });
        if ui
            .checkbox(&mut self.continuous, "Render continuously (measures frame time)")
            .changed()
        {
            self.frame_ms.clear();
            self.last_frame = None;
        }
        self.inspector_controls(ui);
        self.scene_section(ui, ctx);
        self.render_section(ui);
        self.light_section(ui);
        self.method_section(ui);
        ui.collapsing("Presets", |ui| {
            ui.horizontal(|ui| {
                if ui.button("Load preset…").clicked() {
                    self.open_dialog(DialogPurpose::LoadPreset, ctx);
                }
                if ui.button("Save preset…").clicked() {
                    self.open_dialog(DialogPurpose::SavePreset, ctx);
                }
            });
            ui.horizontal_wrapped(|ui| {
                for (name, _) in crate::settings::BUILTIN_PRESETS {
                    if ui.button(*name).clicked() {
                        match crate::settings::Settings::load_preset(name, &[]) {
                            Ok(s) => {
                                self.settings = s;
                                self.rebuild_scene();
                            }
                            Err(e) => self.error(format!("{e:#}")),
                        }
                    }
                }
            });
        });
        self.stats_section(ui);
    }

    /// The switches of the inspector windows.
    fn inspector_controls(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.inspector.open, "Texel inspector")
                .on_hover_text(
                    "V(z) of one light-map texel: click hair in the viewport or a texel in the light map",
                );
            ui.checkbox(&mut self.light_map.open, "Light map")
                .on_hover_text("the light's depth maps and depth complexity; click a texel to inspect it");
        });
    }

    fn scene_section(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        egui::CollapsingHeader::new("Scene")
            .default_open(true)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    if ui.button("Load .hair / glTF…").clicked() {
                        self.open_dialog(DialogPurpose::OpenScene, ctx);
                    }
                    ui.label("or drop a file on the window");
                });
                if let Some(f) = self.settings.scene.file.clone() {
                    ui.horizontal(|ui| {
                        ui.label(format!("file: {}", f.display()));
                        if ui.button("Use generator").clicked() {
                            self.settings.scene.file = None;
                            self.rebuild_scene();
                        }
                    });
                    return;
                }
                let g = &mut self.settings.scene.generator;
                let before = g.clone();
                egui::Grid::new("generator").num_columns(2).show(ui, |ui| {
                    let label = ui.label("kind");
                    let kinds = [
                        (GenKind::Head, "head"),
                        (GenKind::Patch, "patch"),
                        (GenKind::StrayStrand, "stray strand"),
                        (GenKind::MixedSizes, "mixed sizes"),
                        (GenKind::ManyClumps, "many clumps"),
                    ];
                    let current = kinds.iter().find(|(k, _)| *k == g.kind).map_or("?", |(_, n)| *n);
                    egui::ComboBox::from_id_salt("kind")
                        .selected_text(current)
                        .show_ui(ui, |ui| {
                            for (kind, name) in kinds {
                                ui.selectable_value(&mut g.kind, kind, name);
                            }
                        })
                        .response
                        .labelled_by(label.id);
                    ui.end_row();
                    ui.label("style");
                    ui.horizontal(|ui| {
                        ui.selectable_value(&mut g.style, HairStyle::Straight, "straight");
                        ui.selectable_value(&mut g.style, HairStyle::Wavy, "wavy");
                        ui.selectable_value(&mut g.style, HairStyle::Curly, "curly");
                    });
                    ui.end_row();
                    row(
                        ui,
                        "strands",
                        egui::DragValue::new(&mut g.strands).range(1..=200_000).speed(10),
                    );
                    row(
                        ui,
                        "density",
                        egui::Slider::new(&mut g.density, 0.1..=20.0).logarithmic(true),
                    )
                    .on_hover_text("multiplies the strand count: scale up on real GPUs");
                    row(
                        ui,
                        "segments",
                        egui::DragValue::new(&mut g.segments).range(1..=256),
                    );
                    row(
                        ui,
                        "length",
                        egui::DragValue::new(&mut g.length).range(0.01..=2.0).speed(0.005),
                    );
                    row(ui, "clumps", egui::DragValue::new(&mut g.clumps).range(0..=512));
                    row(
                        ui,
                        "clump strength",
                        egui::Slider::new(&mut g.clump_strength, 0.0..=1.0),
                    );
                    row(ui, "seed", egui::DragValue::new(&mut g.seed));
                    row(ui, "floor", egui::Checkbox::without_text(&mut g.floor));
                    row(
                        ui,
                        "strand colours",
                        egui::Checkbox::without_text(&mut g.strand_colors),
                    )
                    .on_hover_text("per-strand colour variation; overrides the hair colour");
                });
                // Regenerate when a drag ends (not on every pixel of it): cheap enough for the default scene.
                if *g != before && !ui.ctx().input(|i| i.pointer.any_down()) {
                    self.rebuild_scene();
                } else if *g != before {
                    ui.ctx().request_repaint();
                } else if self.built_scene.as_ref().is_some_and(|b| b.generator != *g)
                    && !ui.ctx().input(|i| i.pointer.any_down())
                {
                    self.rebuild_scene();
                }
            });
    }

    fn render_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Render")
            .default_open(true)
            .show(ui, |ui| {
                use crate::render::AlphaMode;
                let alpha_modes = |ui: &mut egui::Ui, mode: &mut AlphaMode| {
                    ui.selectable_value(mode, AlphaMode::Constant, "constant")
                        .on_hover_text("every fragment: point alpha × hair alpha");
                    ui.selectable_value(mode, AlphaMode::Coverage, "coverage")
                        .on_hover_text("the strand's coverage of its pixel or light texel × hair alpha");
                };
                let r = &mut self.settings.render;
                egui::Grid::new("render").num_columns(2).show(ui, |ui| {
                    // The alpha mode is the hair-alpha label's context menu, so the default panel keeps its
                    // layout; coverage mode shows the mode and the strand width as rows.
                    let label = ui
                        .add(egui::Label::new("hair alpha").sense(egui::Sense::click()))
                        .on_hover_text("right-click: constant or coverage alpha");
                    label.context_menu(|ui| alpha_modes(ui, &mut r.alpha));
                    ui.add(egui::Slider::new(&mut r.hair_alpha, 0.01..=1.0))
                        .labelled_by(label.id)
                        .on_hover_text(
                            "every fragment's alpha (constant mode) or the strands' material opacity \
                             (coverage mode)",
                        );
                    ui.end_row();
                    if r.alpha == AlphaMode::Coverage {
                        let label = ui.label("alpha mode");
                        egui::ComboBox::from_id_salt("alpha_mode")
                            .selected_text("coverage")
                            .show_ui(ui, |ui| alpha_modes(ui, &mut r.alpha))
                            .response
                            .labelled_by(label.id);
                        ui.end_row();
                        row(
                            ui,
                            "strand width",
                            egui::Slider::new(&mut r.strand_width, 1e-6..=10.0).logarithmic(true),
                        )
                        .on_hover_text(
                            "world width of a strand of thickness 1; alpha = opacity × width / pixel or texel size",
                        );
                    }
                    row(ui, "PCF 3×3", egui::Checkbox::without_text(&mut r.pcf)).on_hover_text(
                        "average the method's visibility over the 3×3 light texels around each point",
                    );
                    row(ui, "jitter", egui::Checkbox::without_text(&mut r.jitter)).on_hover_text(
                        "move each lookup by up to half a light texel (Sintorn & Assarsson §3.3)",
                    );
                    ui.label("hair colour");
                    ui.color_edit_button_rgb(&mut r.hair_color);
                    ui.end_row();
                    ui.label("background");
                    ui.color_edit_button_rgb(&mut r.background);
                    ui.end_row();
                    let label = ui.label("map resolution");
                    egui::ComboBox::from_id_salt("map_res")
                        .selected_text(format!("{0}²", r.map_resolution))
                        .show_ui(ui, |ui| {
                            for &m in MAP_RESOLUTIONS {
                                ui.selectable_value(&mut r.map_resolution, m, format!("{m}²"));
                            }
                        })
                        .response
                        .labelled_by(label.id);
                    ui.end_row();
                });
            });
    }

    fn light_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Light")
            .default_open(true)
            .show(ui, |ui| {
                let l = &mut self.settings.light;
                ui.horizontal(|ui| {
                    ui.selectable_value(&mut l.kind, LightKind::Directional, "directional");
                    ui.selectable_value(&mut l.kind, LightKind::Spot, "spot");
                });
                egui::Grid::new("light").num_columns(2).show(ui, |ui| {
                    row(ui, "azimuth°", egui::Slider::new(&mut l.azimuth_deg, 0.0..=360.0));
                    row(
                        ui,
                        "elevation°",
                        egui::Slider::new(&mut l.elevation_deg, -89.0..=89.0),
                    );
                    row(ui, "intensity", egui::Slider::new(&mut l.intensity, 0.0..=4.0));
                    if l.kind == LightKind::Spot {
                        row(ui, "cone°", egui::Slider::new(&mut l.cone_deg, 1.0..=170.0));
                        row(
                            ui,
                            "distance (radii)",
                            egui::Slider::new(&mut l.distance, 1.01..=20.0),
                        );
                    }
                });
                ui.label("Right-drag in the viewport moves the light.");
            });
    }

    fn method_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Shadow method")
            .default_open(true)
            .show(ui, |ui| {
                let m = &mut self.settings.method;
                let current = registry::find(&m.name).map(|x| x.label()).unwrap_or("?");
                egui::ComboBox::from_label("method")
                    .selected_text(current)
                    .show_ui(ui, |ui| {
                        for (name, label) in method_names() {
                            if ui.selectable_label(m.name == name, label).clicked() && m.name != name {
                                m.name = name.to_string();
                                m.params.clear();
                            }
                        }
                    });
                let Ok(method) = registry::find(&m.name) else {
                    return;
                };
                ui.label(egui::RichText::new(method.info().paper).italics());
                for spec in method.params() {
                    let mut v = methods::value(&m.params, spec);
                    let changed = ui
                        .horizontal(|ui| match spec.kind {
                            ParamKind::Float { min, max, log } => ui
                                .add(
                                    egui::Slider::new(&mut v, min..=max)
                                        .logarithmic(log)
                                        .text(spec.label),
                                )
                                .on_hover_text(spec.help)
                                .changed(),
                            ParamKind::Int { min, max } => {
                                let mut i = v as i32;
                                let c = ui
                                    .add(egui::Slider::new(&mut i, min..=max).text(spec.label))
                                    .on_hover_text(spec.help)
                                    .changed();
                                v = i as f32;
                                c
                            }
                            ParamKind::Choice { options } => {
                                let mut i = (v as usize).min(options.len().saturating_sub(1));
                                let before = i;
                                egui::ComboBox::from_label(spec.label)
                                    .selected_text(options[i])
                                    .show_ui(ui, |ui| {
                                        for (k, o) in options.iter().enumerate() {
                                            ui.selectable_value(&mut i, k, *o);
                                        }
                                    })
                                    .response
                                    .on_hover_text(spec.help);
                                v = i as f32;
                                i != before
                            }
                        })
                        .inner;
                    if changed {
                        m.params.insert(spec.key.to_string(), v);
                    }
                }
                if let Some(a) = method.analysis() {
                    if ui.button(a.label).on_hover_text(a.help).clicked() {
                        self.run_analysis(method, a);
                    }
                    if let Some((name, result)) = &self.analysis
                        && *name == method.name()
                    {
                        ui.label(&result.summary);
                        egui::Grid::new("analysis").striped(true).show(ui, |ui| {
                            for row in &result.table {
                                for cell in row {
                                    ui.label(cell);
                                }
                                ui.end_row();
                            }
                        });
                    }
                }
            });
    }

    fn stats_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Statistics")
            .default_open(true)
            .show(ui, |ui| {
                if let Some(s) = &self.scene {
                    ui.label(format!(
                        "{} strands · {} segments · {} triangles",
                        s.strands.strand_count(),
                        s.strands.segment_count(),
                        s.triangle_count()
                    ));
                }
                if let (Some(r), Ok(m)) = (&self.renderer, registry::find(&self.settings.method.name)) {
                    let mem = r.memory();
                    let passes = r.method_gpu(m).map_or(0, |g| g.geometry_passes());
                    let texels = u64::from(r.map_resolution()).pow(2).max(1);
                    let build = if mem.method_build > 0 {
                        format!(" · built from {}", mib(mem.method_build))
                    } else {
                        String::new()
                    };
                    ui.label(format!(
                        "method maps: {} ({:.1} B per texel){build} · {passes} geometry passes",
                        mib(mem.method()),
                        mem.method() as f64 / texels as f64
                    ));
                    ui.label(format!(
                        "light-depth maps {} · mesh shadow map {} · geometry {} · eye targets {}",
                        mib(mem.light_depth_maps),
                        mib(mem.shadow_map),
                        mib(mem.geometry),
                        mib(mem.eye_targets)
                    ));
                    ui.label(format!("GPU memory total: {}", mib(mem.total())));
                }
                if self.snapshot_mode {
                    return;
                }
                for p in &self.pass_times {
                    ui.label(format!("{:>16}: {:.3} ms", p.name, p.ms));
                }
            });
    }
}
