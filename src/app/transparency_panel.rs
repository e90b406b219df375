//! The side panel's eye transparency section: the technique (every registered one, with its paper), its
//! parameters generated from `info().params` by the method panel's [`param_widgets`], what the held technique
//! costs (geometry passes, memory), the eye depth complexity when known, and the switches of the compare view and
//! the pixel inspector.

use super::HairlabApp;
use super::panels::param_widgets;
use crate::render::transparency::registry;

fn mib(bytes: u64) -> String {
    format!("{:.2} MiB", bytes as f64 / (1024.0 * 1024.0))
}

impl HairlabApp {
    /// Collapsed at start (the window's first screen stays as it was); the compare view and the pixel inspector
    /// are switched on here.
    pub(super) fn transparency_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Transparency")
            .default_open(false)
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.checkbox(&mut self.compare.open, "Compare")
                        .on_hover_text("the paper's Fig. 2: four techniques side by side and their difference");
                    ui.checkbox(&mut self.pixel_inspector.open, "Pixel inspector")
                        .on_hover_text("click hair in the compare view: its exact fragments and every composite");
                });
                let t = &mut self.settings.transparency;
                let current = registry::find(&t.name).map(|x| x.info().label).unwrap_or("?");
                egui::ComboBox::from_label("technique")
                    .selected_text(current)
                    .show_ui(ui, |ui| {
                        for technique in registry::every() {
                            let info = technique.info();
                            let picked = ui
                                .selectable_label(t.name == info.name, info.label)
                                .on_hover_text(info.paper)
                                .clicked();
                            if picked && t.name != info.name {
                                t.name = info.name.to_string();
                                t.params.clear();
                            }
                        }
                    });
                let Ok(technique) = registry::find(&t.name) else {
                    return;
                };
                let info = technique.info();
                ui.label(egui::RichText::new(info.paper).italics());
                let source = ("transparency.params", info.paper);
                param_widgets(ui, "transparency_params", info.params, &mut t.params, source);
                let Some(r) = &self.renderer else { return };
                let mem = r.memory();
                if !mem.transparency_name.is_empty() {
                    ui.label(format!(
                        "held: {} · {} geometry passes · targets {}",
                        mem.transparency_name,
                        r.eye_geometry_passes(),
                        mib(mem.transparency_targets)
                    ));
                }
                if let Some((max, total)) = r.eye_depth_complexity() {
                    ui.label(format!("eye depth complexity: deepest pixel {max} · {total} fragments"));
                }
                if let Some(d) = self.compare.depth_complexity() {
                    ui.label(format!(
                        "eye depth complexity (compare view, {}×{}): max {} · mean {:.1} per hair pixel · {} fragments",
                        d.width, d.height, d.max, d.mean_hair, d.total
                    ));
                }
            });
    }
}
