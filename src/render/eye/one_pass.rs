//! The GPU state of a technique made of one shaded hair pass and its resolve (the blended, order-independent
//! techniques): the hair entry draws into the technique's own targets, one per colour target of the entry, each
//! cleared every frame to its declared value; the resolve reads all of them (group 0) and blends onto the image.

use super::passes::Resolve;
use super::targets::Textures;
use crate::gpu::{Gpu, GpuError};
use crate::render::transparency::{
    EyeFrame, EyeSetup, HairDrawPass, HairEntry, TechniqueInfo, TransparencyGpu,
};

/// What a one-pass technique declares.
pub struct OnePassSpec {
    /// Its constants: the name labels the targets, the first WGSL pass is the resolve (reading the targets at
    /// group 0, bindings 0..).
    pub info: &'static TechniqueInfo,
    /// The hair entry; its colour targets' formats are the targets'.
    pub entry: &'static HairEntry,
    /// The name of each target (in location order) and its clear value.
    pub targets: &'static [(&'static str, [f64; 4])],
    pub blend: wgpu::BlendState,
}

pub struct OnePass {
    spec: &'static OnePassSpec,
    targets: Textures,
    resolve: Resolve,
}

impl OnePass {
    pub fn new(setup: &EyeSetup, spec: &'static OnePassSpec) -> OnePass {
        let device = &setup.gpu.device;
        let declared: Vec<_> = spec
            .targets
            .iter()
            .zip(spec.entry.targets)
            .map(|(&(name, _), t)| (name, t.format))
            .collect();
        OnePass {
            spec,
            targets: Textures::new(device, spec.info.name, &declared, (setup.width, setup.height)),
            resolve: Resolve::of_textures(
                device,
                spec.info.name,
                spec.info.pass_wgsl[0],
                declared.len(),
                spec.blend,
            ),
        }
    }
}

impl TransparencyGpu for OnePass {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        self.targets.resize(&gpu.device, (width, height));
        Ok(())
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        let clears: Vec<_> = self.spec.targets.iter().map(|&(_, clear)| clear).collect();
        frame.draw_hair(
            HairDrawPass {
                entry: self.spec.entry,
                attachments: &self.targets.cleared(&clears),
                depth: None,
                group: None,
                rows: None,
            },
            "eye: hair",
        );
        let views: Vec<_> = (0..clears.len()).map(|i| self.targets.view(i)).collect();
        self.resolve.record_textures(frame, &views);
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        self.targets.bytes()
    }

    fn geometry_passes(&self) -> u32 {
        1
    }
}
