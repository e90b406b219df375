//! The exact eye transparency reference: per-pixel fragment lists (Carpenter 1984's A-buffer, built as the
//! linked lists of Yang et al. 2010), sorted on (depth, segment) so that depth ties keep a total order, and
//! composited back to front onto the opaque image, on the eye toolkit's per-pixel lists ([`PixelLists`]: count,
//! plan, fill in bands, resolve per sort size). Three passes: a count pass over the strands (the fragments per
//! pixel, read back so the node buffer holds exactly the frame's fragments), the shaded fill pass
//! (`transparency/sorted.wgsl`, the list push), and the resolve (`transparency/sorted_resolve.wgsl`), which
//! merge-sorts each pixel's nodes. Memory: 4 B/px heads + 4 B/px counts + 32 B per fragment of the largest band.

use super::{EyeFrame, EyeSetup, EyeTransparency, HairEntry, HairGeometry, TechniqueInfo, TransparencyGpu};
use crate::gpu::{Gpu, GpuError};
use crate::render::eye::lists::{self, BAND_KIB, ListNames, ListSpec, PixelLists};
use crate::render::eye::passes;
use crate::render::eye::pipelines;
use crate::render::method::{ParamValues, Role};
use crate::transparency::{Compositor, EyeFragment, ModelContext};

pub use crate::render::eye::lists::{EyeNode, NODE_BYTES, SORT_SIZES, resolve_source};

static FILL: HairEntry = lists::fill_entry(HairGeometry::Lines);

static INFO: TechniqueInfo = TechniqueInfo {
    name: "sorted",
    label: "Sorted (exact)",
    paper: "Carpenter 1984, The A-buffer; lists as Yang et al. 2010, Real-time concurrent linked list construction",
    role: Role::Reference,
    hair_wgsl: lists::FILL_WGSL,
    hair_entries: std::slice::from_ref(&FILL),
    pass_wgsl: &[
        "transparency/sorted_count.wgsl",
        "transparency/sorted_resolve.wgsl",
    ],
    params: &[BAND_KIB],
    color: [0, 0, 0],
    // f32 front-to-back sums against the model's back-to-front ones; measured 1.2e-7 on lavapipe.
    gpu_tolerance: 1e-5,
};

pub struct Sorted;

impl EyeTransparency for Sorted {
    fn info(&self) -> &'static TechniqueInfo {
        &INFO
    }

    fn create_gpu(&self, setup: &EyeSetup) -> Result<Box<dyn TransparencyGpu>, GpuError> {
        Ok(Box::new(SortedGpu::new(setup)?))
    }

    fn model(&self, _values: &ParamValues, _ctx: &ModelContext) -> Box<dyn Compositor> {
        Box::new(crate::transparency::exact::ExactParams)
    }
}

pub struct SortedGpu {
    lists: PixelLists,
    /// The count pass over the strands (`sorted_count.wgsl`): group 0 the frame, group 1 the counts.
    count_pipeline: wgpu::RenderPipeline,
}

impl SortedGpu {
    fn new(setup: &EyeSetup) -> Result<SortedGpu, GpuError> {
        let lists = PixelLists::new(
            setup.gpu,
            setup.frame_layout,
            (setup.width, setup.height),
            ListSpec {
                label: "sorted",
                what: "eye lists",
                resolve_wgsl: INFO.pass_wgsl[1],
                resolve_extra: &[],
            },
        )?;
        let count_pipeline = pipelines::storage_pass(
            &setup.gpu.device,
            "hairlab.sorted.count",
            INFO.pass_wgsl[0],
            [setup.frame_layout, lists.count_layout()],
            HairGeometry::Lines,
        );
        Ok(SortedGpu {
            lists,
            count_pipeline,
        })
    }
}

impl TransparencyGpu for SortedGpu {
    fn resize(&mut self, gpu: &Gpu, width: u32, height: u32) -> Result<(), GpuError> {
        self.lists.resize(gpu, width, height)
    }

    fn record(&mut self, frame: &mut EyeFrame<'_>) -> Result<(), GpuError> {
        // Pass 1: count.
        let device = &frame.gpu.device;
        let count_group = self.lists.count_group(device, &frame.targets.depth_view);
        self.lists.clear_counts(&mut frame.encoder);
        passes::record_line_count(
            frame,
            "hairlab.sorted.count_pass",
            "eye: count",
            &self.count_pipeline,
            &count_group,
        );
        frame.flush();
        // Pass 2 and 3 per band: fill, resolve.
        let bands = self
            .lists
            .plan(
                frame.gpu,
                frame.output.1,
                crate::render::method::value(frame.values, &INFO.params[0]) as u64 * 1024,
                &ListNames {
                    deep: "transparency.name: the exact reference",
                    rows: "the exact eye reference's",
                    drawn: format!(", {} segments drawn", frame.geometry.hair_index_count / 2),
                },
            )?
            .bands
            .clone();
        let fill_group = self
            .lists
            .fill_group(&frame.gpu.device, &frame.targets.depth_view);
        let resolve_group = self.lists.resolve_group(&frame.gpu.device, &[]);
        for band in bands {
            self.lists.begin_band(&mut frame.encoder);
            self.lists.fill(frame, &FILL, &fill_group, band, "eye: fill");
            self.lists.resolve(frame, &resolve_group, band, "eye: resolve");
        }
        Ok(())
    }

    fn memory_bytes(&self) -> u64 {
        self.lists.memory_bytes()
    }

    fn geometry_passes(&self) -> u32 {
        self.lists.geometry_passes()
    }

    fn read_lists(&self, gpu: &Gpu) -> Option<Result<Vec<Vec<EyeFragment>>, GpuError>> {
        Some(self.lists.read(gpu).map(|lists| {
            lists
                .into_iter()
                .map(|nodes| {
                    let out: Vec<EyeFragment> = nodes
                        .into_iter()
                        .map(|n| EyeFragment {
                            depth: n.depth,
                            segment: n.segment,
                            color: [n.r, n.g, n.b],
                            alpha: n.alpha,
                        })
                        .collect();
                    crate::transparency::front_to_back(&out)
                })
                .collect()
        }))
    }

    fn depth_complexity(&self) -> Option<(u32, u64)> {
        let plan = self.lists.last_plan();
        Some((plan.deepest, plan.fragments))
    }
}
