//! The side panel's Fur section (Andersen et al. 2016; spec B.12): mode (implicit / explicit / hybrid),
//! blending (naive / simplified with `a·h` / virtual with `k`), the shell, the volume's noise and the march, the
//! shell's figures and warnings, and the paper's Table 1 for the last frame, live. The shell is rebuilt when a
//! value it is made of changes; the rest only changes how the next frame renders.

use super::HairlabApp;
use crate::fur::settings::{Blending, FurMode, FurScene, FurSettings, FurView};

/// Whether `a` and `b` build the same shell, volume and environment map.
fn same_shell(a: &FurSettings, b: &FurSettings) -> bool {
    (a.mode == FurMode::Off) == (b.mode == FurMode::Off)
        && a.height == b.height
        && a.layers == b.layers
        && a.max_level == b.max_level
        && a.noise_frequency == b.noise_frequency
        && a.noise_threshold == b.noise_threshold
        && a.noise_softness == b.noise_softness
        && a.env_map == b.env_map
}

impl HairlabApp {
    /// Brings the renderer's fur up to the settings: a new shell when the scene or a shell value changed,
    /// otherwise only the rendering values.
    pub(super) fn sync_fur(&mut self) {
        let (Some(r), Some(scene)) = (self.renderer.as_mut(), self.scene.as_ref()) else {
            return;
        };
        let wanted = &self.settings.fur;
        if let (Some(built), Some(_)) = (&self.built_fur, &self.fur)
            && same_shell(built, wanted)
        {
            if built != wanted {
                r.set_fur_rendering(wanted);
                self.built_fur = Some(wanted.clone());
            }
            return;
        }
        if self.built_fur.as_ref() == Some(wanted) {
            return;
        }
        let built = FurScene::build(scene, wanted)
            .map_err(|e| e.to_string())
            .and_then(|fur| {
                r.set_fur(fur.as_ref().map(|f| (f, wanted)))
                    .map_err(|e| format!("fur: {e}"))?;
                Ok(fur)
            });
        match built {
            Ok(fur) => {
                for w in fur.iter().flat_map(|f| f.warnings.clone()) {
                    self.info(w);
                }
                self.fur = fur;
            }
            Err(e) => {
                self.fur = None;
                self.settings.fur.mode = FurMode::Off;
                self.error(e);
            }
        }
        self.built_fur = Some(self.settings.fur.clone());
    }

    pub(super) fn fur_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Fur")
            .default_open(self.settings.fur.mode != FurMode::Off)
            .show(ui, |ui| {
                ui.label(
                    egui::RichText::new(
                        "Andersen et al. 2016, Hybrid fur rendering: a ray-marched shell on the scene's first mesh \
                         and its strands as guard hairs, in typed per-pixel lists",
                    )
                    .italics(),
                );
                let f = &mut self.settings.fur;
                egui::ComboBox::from_label("mode")
                    .selected_text(f.mode.word())
                    .show_ui(ui, |ui| {
                        for m in FurMode::ALL {
                            ui.selectable_value(&mut f.mode, m, m.word());
                        }
                    });
                if f.mode == FurMode::Off {
                    return;
                }
                egui::ComboBox::from_label("blending")
                    .selected_text(f.blending.word())
                    .show_ui(ui, |ui| {
                        for b in Blending::ALL {
                            ui.selectable_value(&mut f.blending, b, b.word());
                        }
                    });
                egui::ComboBox::from_label("view")
                    .selected_text(f.view.word())
                    .show_ui(ui, |ui| {
                        for v in FurView::ALL {
                            ui.selectable_value(&mut f.view, v, v.word());
                        }
                    })
                    .response
                    .on_hover_text("shaded; fragments coloured by type (guard hair yellow, shell blue, virtual cyan); fragments per pixel");
                match f.blending {
                    Blending::Simplified => {
                        ui.add(
                            egui::Slider::new(&mut f.attenuation, 0.0..=64.0)
                                .logarithmic(true)
                                .text("a·h (eq. 4)"),
                        )
                        .on_hover_text("attenuation a times the shell height: how far behind a shell fragment a guard hair still lowers its alpha");
                    }
                    Blending::Virtual => {
                        ui.add(egui::Slider::new(&mut f.group_steps, 1..=64).text("k (steps per fragment)"))
                            .on_hover_text("march steps per virtual fragment; 1 is the reference");
                    }
                    Blending::Naive => {}
                }
                ui.add(egui::Slider::new(&mut f.base_darkening, 0.0..=4.0).text("guard base darkening β"))
                    .on_hover_text("guard hairs darkened towards the base by the undercoat column above them, exp(−β σ₀ depth); 0: off");
                ui.add(
                    egui::Slider::new(
                        &mut f.env_lights,
                        1..=crate::fur::environment::MAX_ENV_LIGHTS as u32,
                    )
                    .text("guard-hair lights"),
                )
                .on_hover_text("directional lights sampled from a sky around the light for the guard hairs (the paper's 16); 1: the light alone");
                ui.separator();
                ui.add(
                    egui::Slider::new(&mut f.height, 0.001..=0.05)
                        .logarithmic(true)
                        .text("shell height"),
                );
                ui.add(egui::Slider::new(&mut f.layers, 1..=64).text("layers"));
                ui.add(egui::Slider::new(&mut f.max_level, 0..=crate::fur::settings::MAX_LEVEL).text("max subdivision"));
                ui.add(
                    egui::Slider::new(&mut f.noise_frequency, 10.0..=2000.0)
                        .logarithmic(true)
                        .text("noise frequency"),
                );
                ui.add(egui::Slider::new(&mut f.noise_threshold, -1.0..=1.0).text("noise threshold"));
                ui.add(egui::Slider::new(&mut f.density, 0.0..=64.0).text("density σ₀h"));
                ui.add(egui::Slider::new(&mut f.steps_per_thickness, 1..=128).text("steps per height"));
                ui.add(egui::Slider::new(&mut f.max_steps, 1..=1024).text("max steps"));
                ui.add(egui::Slider::new(&mut f.light_steps, 0..=32).text("light steps"));
                if let Some(fur) = &self.fur {
                    ui.label(format!(
                        "{} triangles · {} sub-elements · levels {}..{}",
                        fur.shell.mesh.faces.len(),
                        fur.shell.sub_elements,
                        fur.shell.levels.iter().min().unwrap_or(&0),
                        fur.shell.levels.iter().max().unwrap_or(&0)
                    ));
                }
                self.table1_grid(ui);
            });
    }

    /// Table 1 of the last frame, from its GPU times, as a grid.
    fn table1_grid(&self, ui: &mut egui::Ui) {
        let (Some(r), Some(fur)) = (&self.renderer, &self.fur) else {
            return;
        };
        let Ok(table) = crate::measure::fur::table1(r, fur, self.scene_ms, &self.pass_times) else {
            return;
        };
        egui::CollapsingHeader::new("Table 1 (this frame)")
            .default_open(true)
            .show(ui, |ui| {
                egui::Grid::new("fur_table1").striped(true).show(ui, |ui| {
                    let mib = |b: u64| format!("{:.3} MiB", b as f64 / (1 << 20) as f64);
                    for (i, row) in crate::fur::table::MEMORY_ROWS.iter().enumerate() {
                        ui.label(*row);
                        ui.label(mib(table.memory[i]));
                        ui.end_row();
                    }
                    ui.strong("Total memory");
                    ui.strong(mib(table.total_bytes()));
                    ui.end_row();
                    let ms = |v: f64| {
                        if self.snapshot_mode {
                            "— ms".to_string()
                        } else {
                            format!("{v:.2} ms")
                        }
                    };
                    for (i, row) in crate::fur::table::TIME_ROWS.iter().enumerate() {
                        ui.label(*row);
                        ui.label(ms(table.times[i]));
                        ui.end_row();
                    }
                    for (label, v) in [
                        ("Preprocess time (1–3)", table.preprocess_ms()),
                        ("Online render time (4–7)", table.online_ms()),
                        ("Total render time", table.total_ms()),
                    ] {
                        ui.strong(label);
                        ui.strong(ms(v));
                        ui.end_row();
                    }
                });
            });
    }
}
