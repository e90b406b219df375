//! Per-pass GPU timing with timestamp queries.
//!
//! Each frame a pass asks for [`GpuTimer::pass`] and gets the timestamp writes for its render pass; at the end of
//! the frame the queries are resolved into a readback buffer. Readbacks are non-blocking (a small ring of buffers):
//! [`GpuTimer::poll`] returns the newest finished frame's timings, or [`GpuTimer::wait`] blocks for the CLI.
//!
//! A compute pass's beginning is written at the end of an empty compute pass recorded just before it, its own
//! beginning timestamp going to a scratch query: lavapipe (llvmpipe) takes a timestamp's value when it next
//! flushes (a later timestamp write or a barrier) once a render pass has bound a framebuffer, and runs compute
//! dispatches at once, so a compute pass's own beginning read the clock after its dispatches had run: a 420 ms
//! dispatch after a render pass in one encoder timed 0.0 ms, its time in the gap before the pass.
//! `tests/it/gpu_timing.rs` checks that such a pass now holds its work.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Most passes one frame can time.
pub const MAX_PASSES: u32 = 64;
/// Queries per timed pass: its beginning and end (resolved), and a compute pass's own beginning (a scratch query
/// never resolved; see the module's documentation).
const QUERIES_PER_PASS: u32 = 3;
const RING: usize = 3;

/// What part of a frame a timed pass belongs to: what `measure`, the bench, Table 1 and the status line
/// filter on (a pass's name is for people, never matched).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Phase {
    /// The strand simulation's compute pass (`motion::gpu`), before the frame's passes that draw its points.
    Simulation,
    /// The light passes every method shares (light depth, the meshes' shadow map).
    SharedLight,
    /// The shadow method's own light passes (the exact reference's lists included).
    Method,
    /// The opaque meshes in the eye view.
    Meshes,
    /// The eye transparency technique's passes over the strands (counts, depth ranges, moments, shaded hair).
    EyeHair,
    /// The fur shell's ray march in the eye view.
    FurShell,
    /// The technique's resolve onto the image.
    Resolve,
}

impl Phase {
    /// Every phase, in frame order.
    pub const ALL: [Phase; 7] = [
        Phase::Simulation,
        Phase::SharedLight,
        Phase::Method,
        Phase::Meshes,
        Phase::EyeHair,
        Phase::FurShell,
        Phase::Resolve,
    ];

    /// A short word for tables and the status line.
    pub fn label(self) -> &'static str {
        match self {
            Phase::Simulation => "simulation",
            Phase::SharedLight => "shared light",
            Phase::Method => "method",
            Phase::Meshes => "meshes",
            Phase::EyeHair => "eye hair",
            Phase::FurShell => "fur shell",
            Phase::Resolve => "resolve",
        }
    }

    /// Whether the phase is the eye transparency technique's own work (what `measure transparency` times).
    pub fn is_technique(self) -> bool {
        matches!(self, Phase::EyeHair | Phase::FurShell | Phase::Resolve)
    }
}

/// GPU time of one pass in milliseconds.
#[derive(Clone, Debug, PartialEq)]
pub struct PassTime {
    pub phase: Phase,
    pub name: String,
    pub ms: f64,
}

/// Total milliseconds of the passes of `phase` in `times` (0, not the empty sum's −0, when there are none).
pub fn phase_ms(times: &[PassTime], phase: Phase) -> f64 {
    times
        .iter()
        .filter(|t| t.phase == phase)
        .map(|t| t.ms)
        .sum::<f64>()
        + 0.0
}

struct Slot {
    buffer: wgpu::Buffer,
    names: Vec<(Phase, String)>,
    ready: Arc<AtomicBool>,
    in_flight: bool,
}

/// One timer entry spanning several render passes (see [`GpuTimer::span`]).
pub struct TimerSpan {
    queries: wgpu::QuerySet,
    index: u32,
}

impl TimerSpan {
    /// Timestamp writes of the span's first pass: its beginning.
    pub fn first(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(2 * self.index),
            end_of_pass_write_index: None,
        }
    }

    /// Timestamp writes of a compute pass of the span: the span's beginning when `first` (written by an empty
    /// compute pass recorded into `encoder` before it: [`GpuTimer::compute_pass`]), its end when `last` (both for
    /// a span of one pass; `None` for a pass in between).
    pub fn compute(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        first: bool,
        last: bool,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        if first {
            begin_before(encoder, &self.queries, self.index);
        }
        (first || last).then(|| wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: first.then_some(scratch_index(self.index)),
            end_of_pass_write_index: last.then_some(2 * self.index + 1),
        })
    }

    /// Timestamp writes of the span's last pass: its end.
    pub fn last(&self) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: None,
            end_of_pass_write_index: Some(2 * self.index + 1),
        }
    }
}

/// The scratch query of timed pass `i`: a compute pass's own beginning, never read.
fn scratch_index(i: u32) -> u32 {
    2 * MAX_PASSES + i
}

/// Records an empty compute pass into `encoder` whose end writes timed pass `i`'s beginning.
fn begin_before(encoder: &mut wgpu::CommandEncoder, queries: &wgpu::QuerySet, i: u32) {
    encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some("hairlab.timing.begin"),
        timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
            query_set: queries,
            beginning_of_pass_write_index: None,
            end_of_pass_write_index: Some(2 * i),
        }),
    });
}

pub struct GpuTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    slots: Vec<Slot>,
    current: usize,
    names: Vec<(Phase, String)>,
    period_ns: f64,
    latest: Vec<PassTime>,
}

impl GpuTimer {
    /// `None` when the device has no timestamp queries.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Option<GpuTimer> {
        if !device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
            return None;
        }
        let count = MAX_PASSES * QUERIES_PER_PASS;
        let bytes = u64::from(MAX_PASSES) * 2 * 8;
        let queries = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("hairlab.timing.queries"),
            ty: wgpu::QueryType::Timestamp,
            count,
        });
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("hairlab.timing.resolve"),
            size: bytes,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let slots = (0..RING)
            .map(|i| Slot {
                buffer: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(&format!("hairlab.timing.readback{i}")),
                    size: bytes,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                names: Vec::new(),
                ready: Arc::new(AtomicBool::new(false)),
                in_flight: false,
            })
            .collect();
        Some(GpuTimer {
            queries,
            resolve,
            slots,
            current: 0,
            names: Vec::new(),
            period_ns: queue.get_timestamp_period() as f64,
            latest: Vec::new(),
        })
    }

    /// Timestamp writes for the next pass of this frame, of `phase` (`None` once [`MAX_PASSES`] are used).
    pub fn pass(
        &mut self,
        phase: Phase,
        name: impl Into<String>,
    ) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        let i = self.next(phase, name)?;
        Some(wgpu::RenderPassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(2 * i),
            end_of_pass_write_index: Some(2 * i + 1),
        })
    }

    /// Timestamp writes for the next compute pass of this frame, to be recorded into `encoder` next: its
    /// beginning is written by an empty compute pass recorded here (see the module's documentation).
    pub fn compute_pass(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        phase: Phase,
        name: impl Into<String>,
    ) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        let i = self.next(phase, name)?;
        begin_before(encoder, &self.queries, i);
        Some(wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(scratch_index(i)),
            end_of_pass_write_index: Some(2 * i + 1),
        })
    }

    /// One entry named `name` timing several passes as one, from the beginning of the first (`TimerSpan::first`)
    /// to the end of the last (`TimerSpan::last`): for more passes than [`MAX_PASSES`] (a depth peel's layers).
    pub fn span(&mut self, phase: Phase, name: impl Into<String>) -> Option<TimerSpan> {
        let index = self.next(phase, name)?;
        Some(TimerSpan {
            queries: self.queries.clone(),
            index,
        })
    }

    fn next(&mut self, phase: Phase, name: impl Into<String>) -> Option<u32> {
        let i = self.names.len() as u32;
        if i >= MAX_PASSES {
            return None;
        }
        self.names.push((phase, name.into()));
        Some(i)
    }

    /// Resolves this frame's queries; call once after the frame's passes are recorded, before submitting.
    /// Returns false (and drops this frame's timings) when every readback buffer is still in flight.
    pub fn resolve(&mut self, encoder: &mut wgpu::CommandEncoder) -> bool {
        let names = std::mem::take(&mut self.names);
        if names.is_empty() {
            return false;
        }
        let Some(idx) = (0..RING)
            .map(|k| (self.current + k) % RING)
            .find(|&k| !self.slots[k].in_flight)
        else {
            return false;
        };
        let n = names.len() as u32 * 2;
        encoder.resolve_query_set(&self.queries, 0..n, &self.resolve, 0);
        let slot = &mut self.slots[idx];
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &slot.buffer, 0, n as u64 * 8);
        slot.names = names;
        self.current = idx;
        true
    }

    /// Starts the readback of the frame just resolved; call right after submitting it.
    pub fn after_submit(&mut self) {
        let slot = &mut self.slots[self.current];
        if slot.in_flight || slot.names.is_empty() {
            return;
        }
        slot.in_flight = true;
        slot.ready.store(false, Ordering::SeqCst);
        let ready = slot.ready.clone();
        slot.buffer.map_async(wgpu::MapMode::Read, .., move |r| {
            ready.store(r.is_ok(), Ordering::SeqCst)
        });
        self.current = (self.current + 1) % RING;
    }

    /// Collects finished readbacks without blocking; returns the newest known timings.
    pub fn poll(&mut self, device: &wgpu::Device) -> &[PassTime] {
        let _ = device.poll(wgpu::PollType::Poll);
        self.collect();
        &self.latest
    }

    /// Blocks until every readback in flight has finished; returns the newest timings.
    pub fn wait(&mut self, device: &wgpu::Device) -> &[PassTime] {
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        self.collect();
        &self.latest
    }

    fn collect(&mut self) {
        for slot in &mut self.slots {
            if !slot.in_flight || !slot.ready.load(Ordering::SeqCst) {
                continue;
            }
            let n = slot.names.len() * 2;
            if let Ok(view) = slot.buffer.get_mapped_range(..) {
                let ticks: &[u64] = bytemuck::cast_slice(&view[..n * 8]);
                self.latest = slot
                    .names
                    .iter()
                    .enumerate()
                    .map(|(i, (phase, name))| PassTime {
                        phase: *phase,
                        name: name.clone(),
                        ms: ticks[2 * i + 1].saturating_sub(ticks[2 * i]) as f64 * self.period_ns * 1e-6,
                    })
                    .collect();
            }
            slot.buffer.unmap();
            slot.in_flight = false;
            slot.ready.store(false, Ordering::SeqCst);
        }
    }
}
