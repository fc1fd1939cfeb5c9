//! Per-pass GPU timestamps that never stall a frame.
//!
//! Each pass writes a begin/end timestamp pair (pass-level timestamp writes,
//! which every adapter with `TIMESTAMP_QUERY` has; writes inside passes are
//! missing on some). At the end of a frame the queries are resolved into one
//! of a small ring of readback buffers, which is mapped asynchronously; the
//! figures are read one or two frames later, when the mapping has completed.
//! A frame that finds every slot still in flight records no timestamps
//! rather than wait.

use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Arc;

/// Readback slots: a frame's timings arrive at most this many frames late
/// before the ring runs out and frames go untimed.
const SLOTS: usize = 3;

const FREE: u8 = 0;
const MAPPING: u8 = 1;
const MAPPED: u8 = 2;
const FAILED: u8 = 3;

/// The per-pass timings of one frame: milliseconds by pass index of the
/// schedule that recorded it.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameStamps {
    /// The frame number the caller gave `resolve`.
    pub frame: u64,
    /// None for a pass that did not run in that frame.
    pub ms: Vec<Option<f64>>,
}

struct Slot {
    read: wgpu::Buffer,
    state: Arc<AtomicU8>,
    frame: u64,
    /// Which passes wrote their timestamps in that frame.
    ran: Vec<bool>,
}

/// Begin/end timestamps for every pass of a schedule, read back through a
/// ring of buffers (see the module docs).
pub struct PassTimer {
    query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    slots: Vec<Slot>,
    passes: u32,
    period_ns: f32,
    /// The slot the current frame resolves into, if one was free.
    current: Option<usize>,
}

impl PassTimer {
    /// A timer for a schedule of `passes` passes.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, passes: usize) -> PassTimer {
        let count = (2 * passes.max(1)) as u32;
        let size = u64::from(count) * 8;
        let slots = (0..SLOTS)
            .map(|_| Slot {
                read: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("timestamp read"),
                    size,
                    usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                    mapped_at_creation: false,
                }),
                state: Arc::new(AtomicU8::new(FREE)),
                frame: 0,
                ran: Vec::new(),
            })
            .collect();
        PassTimer {
            query_set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            slots,
            passes: passes as u32,
            period_ns: queue.get_timestamp_period(),
            current: None,
        }
    }

    /// Picks a free slot for the frame about to be recorded; false when all
    /// are still in flight (the frame then goes untimed).
    pub fn begin_frame(&mut self) -> bool {
        self.current = if self.passes == 0 { None } else { self.slots.iter().position(|s| s.state.load(Ordering::Acquire) == FREE) };
        self.current.is_some()
    }

    /// Timestamp writes for pass `pass`, when this frame is timed: the
    /// begin stamp on its first compute pass, the end stamp on its last
    /// (a pass of several dispatches is timed as a whole).
    pub fn writes(&self, pass: usize, first: bool, last: bool) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.current?;
        if !first && !last {
            return None;
        }
        Some(wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: first.then_some(2 * pass as u32),
            end_of_pass_write_index: last.then_some(2 * pass as u32 + 1),
        })
    }

    /// Records the resolve and the copy into this frame's slot at the end
    /// of the frame's encoder; `ran` says which passes wrote stamps.
    pub fn resolve(&mut self, enc: &mut wgpu::CommandEncoder, frame: u64, ran: Vec<bool>) {
        let Some(i) = self.current else { return };
        enc.resolve_query_set(&self.query_set, 0..2 * self.passes, &self.resolve, 0);
        enc.copy_buffer_to_buffer(&self.resolve, 0, &self.slots[i].read, 0, self.resolve.size());
        self.slots[i].frame = frame;
        self.slots[i].ran = ran;
    }

    /// After the frame was submitted: starts mapping its slot.
    pub fn after_submit(&mut self) {
        let Some(i) = self.current.take() else { return };
        let slot = &self.slots[i];
        slot.state.store(MAPPING, Ordering::Release);
        let state = Arc::clone(&slot.state);
        slot.read.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            state.store(if r.is_ok() { MAPPED } else { FAILED }, Ordering::Release);
        });
    }

    /// Every frame whose timings have arrived, oldest first; never waits
    /// (the caller polls the device). Slots whose mapping failed are freed.
    pub fn collect(&mut self) -> Vec<FrameStamps> {
        let mut done = Vec::new();
        for slot in &mut self.slots {
            match slot.state.load(Ordering::Acquire) {
                MAPPED => {
                    if let Ok(view) = slot.read.slice(..).get_mapped_range() {
                        let ticks: Vec<u64> =
                            view.chunks_exact(8).map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8]))).collect();
                        let ms = (0..self.passes as usize)
                            .map(|p| {
                                let ran = slot.ran.get(p).copied().unwrap_or(true);
                                ran.then(|| ticks[2 * p + 1].saturating_sub(ticks[2 * p]) as f64 * f64::from(self.period_ns) / 1e6)
                            })
                            .collect();
                        done.push(FrameStamps { frame: slot.frame, ms });
                    }
                    slot.read.unmap();
                    slot.state.store(FREE, Ordering::Release);
                }
                FAILED => slot.state.store(FREE, Ordering::Release),
                _ => {}
            }
        }
        done.sort_by_key(|f| f.frame);
        done
    }

    /// Whether any slot is still waiting for its frame.
    pub fn in_flight(&self) -> bool {
        self.slots.iter().any(|s| s.state.load(Ordering::Acquire) == MAPPING)
    }
}
