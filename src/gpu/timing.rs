//! Per-pass GPU timestamps: one query pair per pass, resolved and read back
//! after the frame.

use crate::error::UserError;
use crate::gpu::readback::map_buffer;

pub struct PassTimer {
    pub query_set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    passes: u32,
    period_ns: f32,
}

impl PassTimer {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, passes: usize) -> PassTimer {
        let count = (2 * passes.max(1)) as u32;
        let size = u64::from(count) * 8;
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
            read: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp read"),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
            passes: passes as u32,
            period_ns: queue.get_timestamp_period(),
        }
    }

    pub fn writes(&self, pass: usize) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.query_set,
            beginning_of_pass_write_index: Some(2 * pass as u32),
            end_of_pass_write_index: Some(2 * pass as u32 + 1),
        }
    }

    /// Records the resolve and copy at the end of a frame's encoder.
    pub fn resolve(&self, enc: &mut wgpu::CommandEncoder) {
        if self.passes == 0 {
            return;
        }
        enc.resolve_query_set(&self.query_set, 0..2 * self.passes, &self.resolve, 0);
        enc.copy_buffer_to_buffer(&self.resolve, 0, &self.read, 0, self.resolve.size());
    }

    /// Milliseconds per pass of the last submitted frame (waits for it).
    pub fn read_ms(&self, device: &wgpu::Device) -> Result<Vec<f64>, UserError> {
        if self.passes == 0 {
            return Ok(vec![]);
        }
        let bytes = map_buffer(device, &self.read)?;
        let ticks: Vec<u64> = bytes.chunks_exact(8).map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8]))).collect();
        Ok((0..self.passes as usize)
            .map(|p| ticks[2 * p + 1].saturating_sub(ticks[2 * p]) as f64 * f64::from(self.period_ns) / 1e6)
            .collect())
    }
}
