//! One key type and one cache for the pipelines of the passes that paste plug-in WGSL (the mesh and hair eye
//! passes, the evaluation pass): each pipeline is built on first use and kept for every later frame with the same
//! key. The key names everything the pipeline is built from besides the pass itself: the shadow method (its lookup
//! and group-1 layout) and, for the hair pass, the eye transparency technique (its store function and targets).
//!
//! And the base descriptor of the compute passes ([`ComputePass`], in the style of the eye toolkit's
//! `eye::pipelines`): a pass declares its module, entry and groups; its groups of buffers are declared as a list of
//! bindings (`eye::bindings::layout_for`) and bound whole in order ([`buffer_group`]).

use std::collections::HashMap;

/// A pass whose pipelines are cached by [`PipelineKey`].
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub enum Pass {
    Mesh,
    Hair,
    /// The hair pass drawing camera-facing ribbons (a hair entry of `HairGeometry::Ribbons`).
    HairRibbons,
    Evaluate,
}

impl Pass {
    /// The pass's name in GPU labels (`hairlab.<pass>.<resource>`).
    pub fn name(self) -> &'static str {
        match self {
            Pass::Mesh => "mesh",
            Pass::Hair => "hair",
            Pass::HairRibbons => "hair_ribbons",
            Pass::Evaluate => "evaluate",
        }
    }
}

/// What a cached pipeline is built from.
#[derive(Clone, Copy, Debug, Hash, PartialEq, Eq)]
pub struct PipelineKey {
    pub pass: Pass,
    /// The shadow method whose lookup the pass pastes.
    pub method: &'static str,
    /// The eye transparency technique and its hair fragment entry point whose colour targets the pass uses;
    /// `None` for the passes that do not depend on it (mesh, evaluate), so they build one pipeline per method,
    /// not per pair.
    pub technique: Option<(&'static str, &'static str)>,
}

impl PipelineKey {
    /// `hairlab.<pass>.<resource>`.
    pub fn label(&self, resource: &str) -> String {
        format!("hairlab.{}.{resource}", self.pass.name())
    }
}

/// Pipelines (render or compute) by key, each built once.
pub struct PipelineCache<P> {
    pipelines: HashMap<PipelineKey, P>,
    /// Pipelines built so far.
    built: u64,
}

impl<P> Default for PipelineCache<P> {
    fn default() -> Self {
        PipelineCache {
            pipelines: HashMap::new(),
            built: 0,
        }
    }
}

impl<P> PipelineCache<P> {
    /// The pipeline of `key`, built by `build` when the cache does not hold it yet.
    pub fn get_or_build(&mut self, key: PipelineKey, build: impl FnOnce(&PipelineKey) -> P) -> &P {
        let built = &mut self.built;
        self.pipelines.entry(key).or_insert_with(|| {
            *built += 1;
            build(&key)
        })
    }

    /// How many pipelines this cache has built (a pipeline dropped and built again counts twice).
    pub fn built(&self) -> u64 {
        self.built
    }

    /// Drops the pipelines of `technique` (its GPU state, whose group-2 layout they were built with, is new).
    pub fn forget_technique(&mut self, technique: &str) {
        self.pipelines
            .retain(|k, _| k.technique.is_none_or(|(t, _)| t != technique));
    }
}

/// A compute pass as it declares itself.
pub struct ComputePass<'a> {
    pub label: &'a str,
    pub module: &'a wgpu::ShaderModule,
    pub entry: &'a str,
    /// Groups 0.. of the pipeline.
    pub layouts: &'a [&'a wgpu::BindGroupLayout],
}

/// The pipeline of `pass`.
pub fn compute(device: &wgpu::Device, pass: &ComputePass) -> wgpu::ComputePipeline {
    let layouts: Vec<_> = pass.layouts.iter().copied().map(Some).collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(pass.label),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(pass.label),
        layout: Some(&layout),
        module: pass.module,
        entry_point: Some(pass.entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

/// A group over `buffers`, each bound whole at bindings 0.. in order.
pub fn buffer_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let resources: Vec<_> = buffers.iter().map(|b| b.as_entire_binding()).collect();
    crate::render::eye::bindings::group(device, label, layout, &resources)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(pass: Pass, method: &'static str, technique: Option<(&'static str, &'static str)>) -> PipelineKey {
        PipelineKey {
            pass,
            method,
            technique,
        }
    }

    #[test]
    fn each_key_is_built_once_and_every_field_tells_keys_apart() {
        let mut cache = PipelineCache::default();
        let builds = std::cell::Cell::new(0);
        let get = |cache: &mut PipelineCache<String>, k: PipelineKey| {
            cache
                .get_or_build(k, |k| {
                    builds.set(builds.get() + 1);
                    format!("{}:{}:{:?}", k.label("pipeline"), k.method, k.technique)
                })
                .clone()
        };
        let hair = key(Pass::Hair, "method-a", Some(("technique-a", "fs_main")));
        assert_eq!(
            get(&mut cache, hair),
            "hairlab.hair.pipeline:method-a:Some((\"technique-a\", \"fs_main\"))"
        );
        assert_eq!(
            get(&mut cache, hair),
            "hairlab.hair.pipeline:method-a:Some((\"technique-a\", \"fs_main\"))"
        );
        get(&mut cache, key(Pass::Mesh, "method-a", None));
        get(
            &mut cache,
            key(Pass::Hair, "method-b", Some(("technique-a", "fs_main"))),
        );
        get(
            &mut cache,
            key(Pass::Hair, "method-a", Some(("technique-b", "fs_main"))),
        );
        get(
            &mut cache,
            key(Pass::Hair, "method-a", Some(("technique-a", "fs_other"))),
        );
        get(&mut cache, key(Pass::Hair, "method-a", None));
        assert_eq!(
            get(&mut cache, key(Pass::Evaluate, "method-a", None)),
            "hairlab.evaluate.pipeline:method-a:None"
        );
        assert_eq!(builds.get(), 7);
        cache.forget_technique("technique-a");
        get(&mut cache, hair);
        get(
            &mut cache,
            key(Pass::Hair, "method-a", Some(("technique-b", "fs_main"))),
        );
        assert_eq!(builds.get(), 8, "only technique-a's pipelines were dropped");
        assert_eq!(cache.built(), 8);
    }
}
