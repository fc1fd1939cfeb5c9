//! The window shows the scene's latest finished image, not its frame in
//! progress. The scene renders on a device of its own and the window (egui,
//! the present pass, the surface) on another, so a frame that takes
//! seconds leaves the panel live: on a CPU driver one device's queue runs
//! its work in order, and a window frame queued behind a multi-second
//! path-traced frame would wait for it (on lavapipe two devices' queues
//! run side by side). After each scene frame's passes, in its submission,
//! the texture shown (the output or the resource picked in the panel) is
//! copied into a buffer;
//! once the scene's device has finished and mapped it, it is written into
//! a texture of the same format on the window's device.

use std::sync::mpsc::{channel, Receiver, TryRecvError};

use crate::error::UserError;
use crate::format::TexFormat;
use crate::gpu::Gpu;
use crate::graph::pipelines::wgpu_format;

/// A copy on its way from the scene's device.
struct InFlight {
    buffer: wgpu::Buffer,
    mapped: Receiver<Result<(), wgpu::BufferAsyncError>>,
    format: TexFormat,
    size: (u32, u32),
    /// Bytes per row in the buffer (padded to wgpu's copy alignment).
    row: u32,
}

/// The scene image on the window's device, and the copy in flight.
pub struct Mirror {
    /// Tells the waiter thread a frame was submitted: it waits for the
    /// scene's device there and wakes the window the moment the copy is
    /// mapped (the window's thread never polls for it).
    submitted_to: Option<std::sync::mpsc::Sender<()>>,
    /// That thread, joined on drop: one still inside the driver when the
    /// process exits crashes it (lavapipe is torn down under it).
    waiter: Option<std::thread::JoinHandle<()>>,
    shown: Option<(wgpu::Texture, TexFormat)>,
    /// A copy recorded into a frame not yet submitted.
    recorded: Option<(wgpu::Buffer, TexFormat, (u32, u32), u32)>,
    /// The last copy's buffer, unmapped, for the next copy of the same
    /// size (no buffer is made every frame).
    spare: Option<wgpu::Buffer>,
    in_flight: Option<InFlight>,
}

impl Mirror {
    /// A mirror of `scene`'s images; `wake` is called when one arrives.
    pub fn new(scene: &Gpu, wake: crate::viewer::Waker) -> Result<Mirror, UserError> {
        let (submitted_to, submissions) = channel::<()>();
        let device = scene.device.clone();
        let waiter = std::thread::Builder::new()
            .name("glint frame waiter".into())
            .spawn(move || {
                // Ends when the mirror is dropped. A timeout is left to the
                // window, which shows a frame that never finishes.
                while submissions.recv().is_ok() {
                    let _ = device.poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(crate::gpu::gpu_timeout()) });
                    wake();
                }
            })
            .map_err(|e| UserError::new(format!("cannot start the frame waiter thread: {e}")))?;
        Ok(Mirror { submitted_to: Some(submitted_to), waiter: Some(waiter), shown: None, recorded: None, spare: None, in_flight: None })
    }

    /// Whether a copy is still on its way (the scene's frame is running).
    pub fn busy(&self) -> bool {
        self.in_flight.is_some()
    }

    /// The last image that arrived, on the window's device.
    pub fn shown(&self) -> Option<(&wgpu::Texture, TexFormat)> {
        self.shown.as_ref().map(|(t, f)| (t, *f))
    }

    /// Records the copy of `texture` into the frame's encoder (after its
    /// passes: a second submission would wait for the frame on a CPU
    /// driver); `submitted` asks for the buffer once it is submitted.
    pub fn record(&mut self, device: &wgpu::Device, enc: &mut wgpu::CommandEncoder, texture: &wgpu::Texture, format: TexFormat) {
        let size = (texture.width(), texture.height());
        let row = (size.0 * format.bytes_per_pixel() as u32).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let bytes = u64::from(row) * u64::from(size.1);
        let buffer = match self.spare.take() {
            Some(b) if b.size() == bytes => b,
            _ => device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("mirror"),
                size: bytes,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
        };
        enc.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo { buffer: &buffer, layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(size.1) } },
            wgpu::Extent3d { width: size.0, height: size.1, depth_or_array_layers: 1 },
        );
        self.recorded = Some((buffer, format, size, row));
    }

    /// After the frame with the recorded copy was submitted: the buffer is
    /// mapped once the frame is done.
    pub fn submitted(&mut self) {
        let Some((buffer, format, size, row)) = self.recorded.take() else { return };
        let (tx, mapped) = channel();
        buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.in_flight = Some(InFlight { buffer, mapped, format, size, row });
        // The waiter is gone only if its thread died; the window's own
        // polls still take the image in then.
        if let Some(to) = &self.submitted_to {
            let _ = to.send(());
        }
    }

    /// Takes in the copy if it has arrived (with `wait`, waits for it):
    /// true when a new image is now shown.
    pub fn poll(&mut self, scene: &Gpu, window: &Gpu, wait: bool) -> Result<bool, UserError> {
        let Some(f) = &self.in_flight else { return Ok(false) };
        let result = if wait {
            if !scene.wait() {
                return Err(UserError::new("the scene's frame did not finish in time (GLINT_GPU_TIMEOUT_S sets the limit)"));
            }
            // The frame is done, but the waiter thread's poll may be the one
            // delivering the mapping's callback: wait for it.
            match f.mapped.recv_timeout(crate::gpu::gpu_timeout()) {
                Ok(r) => Ok(r),
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => Err(TryRecvError::Empty),
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => Err(TryRecvError::Disconnected),
            }
        } else {
            let _ = scene.device.poll(wgpu::PollType::Poll);
            f.mapped.try_recv()
        };
        let mapped = match result {
            Ok(r) => r,
            Err(TryRecvError::Empty) => return Ok(false),
            Err(TryRecvError::Disconnected) => Err(wgpu::BufferAsyncError),
        };
        let Some(f) = self.in_flight.take() else { return Ok(false) };
        mapped.map_err(|e| UserError::new(format!("copying the scene's image to the window failed: {e}")))?;
        let fits = self.shown.as_ref().is_some_and(|(t, format)| *format == f.format && (t.width(), t.height()) == f.size);
        if !fits {
            let texture = window.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("shown"),
                size: wgpu::Extent3d { width: f.size.0, height: f.size.1, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu_format(f.format),
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            self.shown = Some((texture, f.format));
        }
        if let Some((texture, _)) = &self.shown {
            let bytes = f.buffer.get_mapped_range(..).map_err(|e| UserError::new(format!("copying the scene's image to the window failed: {e}")))?;
            window.queue.write_texture(
                texture.as_image_copy(),
                &bytes,
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(f.row), rows_per_image: Some(f.size.1) },
                wgpu::Extent3d { width: f.size.0, height: f.size.1, depth_or_array_layers: 1 },
            );
        }
        f.buffer.unmap();
        self.spare = Some(f.buffer);
        Ok(true)
    }
}

impl Drop for Mirror {
    /// Ends the waiter thread (its channel closes) and waits for it, which
    /// lasts at most until the frame in flight is done.
    fn drop(&mut self) {
        self.submitted_to = None;
        if let Some(w) = self.waiter.take() {
            let _ = w.join();
        }
    }
}
