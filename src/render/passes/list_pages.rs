//! What the passes over the light A-buffer's lists share (`abuffer`, `list_sort`, the compressors AVSM and the
//! compressed deep shadow map): the loop budget of a CPU adapter, and compute pipelines made per count of node
//! pages.

/// Node pages (storage bindings) of an A-buffer: the nodes fit `NODE_PAGES` × the device's storage binding size
/// (1 GiB of nodes, 67 M fragments, on a 128 MiB binding).
pub const NODE_PAGES: usize = 8;

/// Loop iterations one invocation of a compute pass that sorts or walks the lists (`list_sort`; AVSM's and the
/// compressed deep shadow map's walks, `shaders/common/list_walk.wgsl`) may take on a CPU adapter in one
/// dispatch: llvmpipe (lavapipe) stops a shader's loops after 65,535 iterations in all (measured with AVSM at 8
/// nodes walked in one dispatch: a 220-fragment list, 220 × (220 + 61) = 61,820 iterations, equals the CPU
/// model; 244, 74,420, does not). The margin covers the loops outside the walk.
pub const CPU_ADAPTER_LOOP_BUDGET: u64 = 60_000;

/// A compute pipeline over an A-buffer's lists, one variant per count of node pages (the `list_pages` constant of
/// `shaders/common/list_node.wgsl`: an access tests those pages only), each made when first needed
/// ([`ListPipeline::prepare`]) and picked by [`ListPipeline::for_pages`].
pub struct ListPipeline {
    label: String,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    entry: String,
    /// Index: pages − 1.
    variants: Vec<Option<wgpu::ComputePipeline>>,
}

impl ListPipeline {
    pub fn new(
        label: &str,
        layout: &wgpu::PipelineLayout,
        module: &wgpu::ShaderModule,
        entry: &str,
    ) -> ListPipeline {
        ListPipeline {
            label: label.to_owned(),
            layout: layout.clone(),
            module: module.clone(),
            entry: entry.to_owned(),
            variants: vec![None; NODE_PAGES],
        }
    }

    /// Makes the variant for lists in `pages` pages (`ABuffer::pages_used` after this frame's prepare).
    pub fn prepare(&mut self, device: &wgpu::Device, pages: usize) {
        if self.variants[pages - 1].is_none() {
            self.variants[pages - 1] =
                Some(device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(&self.label),
                    layout: Some(&self.layout),
                    module: &self.module,
                    entry_point: Some(&self.entry),
                    compilation_options: wgpu::PipelineCompilationOptions {
                        constants: &[("list_pages", pages as f64)],
                        ..Default::default()
                    },
                    cache: None,
                }));
        }
    }

    /// The variant for lists in `pages` pages (made by [`ListPipeline::prepare`] this frame).
    pub fn for_pages(&self, pages: usize) -> &wgpu::ComputePipeline {
        self.variants[pages - 1]
            .as_ref()
            .expect("ListPipeline::prepare runs before recording")
    }
}
