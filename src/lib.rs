//! hairlab: a workbench for real-time hair self-shadowing methods, side by side on the same strands.
#![allow(clippy::too_many_arguments)]

pub mod animation;
pub mod app;
pub mod bench;
pub mod cli;
pub mod fur;
pub mod gpu;
pub mod io;
pub mod live_shaders;
pub mod measure;
pub mod methods;
pub mod motion;
pub mod pathtrace;
pub mod render;
pub mod rng;
pub mod scene;
pub mod selection;
pub mod settings;
pub mod shaders;
pub mod shading;
pub mod soak;
pub mod transparency;
pub mod visibility;

#[cfg(test)]
mod tests {
    /// Dependencies run one way: the renderer (and the GPU, scene and CPU-model modules under it) never import
    /// the shadow methods, the settings, the app, the bench or `measure`, which sit above it.
    #[test]
    fn lower_layers_import_nothing_above_them() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
        let above = [
            "crate::methods",
            "crate::settings",
            "crate::app",
            "crate::bench",
            "crate::measure",
        ];
        let mut checked = 0;
        let mut stack: Vec<_> = [
            "render",
            "gpu",
            "scene",
            "visibility",
            "transparency",
            "fur",
            "motion",
            "shading",
        ]
        .iter()
        .map(|d| root.join(d))
        .collect();
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                    continue;
                }
                let text = std::fs::read_to_string(&path).unwrap();
                for (i, line) in text.lines().enumerate() {
                    let code = line.trim_start();
                    if code.starts_with("//") || code.contains("\"crate::") {
                        continue;
                    }
                    for a in above {
                        assert!(!code.contains(a), "{}:{}: imports {a}", path.display(), i + 1);
                    }
                }
                checked += 1;
            }
        }
        assert!(checked > 20, "only {checked} files checked");
    }
}
