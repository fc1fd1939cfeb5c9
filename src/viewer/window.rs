//! The viewer's window: its size and title before it opens, and the
//! surface format it draws in.

use winit::window::{Window, WindowAttributes};

use crate::viewer::ViewOptions;

/// Width of the side panel in logical pixels.
pub const PANEL_WIDTH: f32 = 340.0;

/// The window's least height: the side panel's sections fit without
/// scrolling (logical pixels).
const MIN_WINDOW_HEIGHT: u32 = 760;
/// The largest window side asked for, in logical pixels.
const MAX_WINDOW_SIDE: f64 = 8192.0;

/// The window for `options`: the panel beside the render size, at least
/// MIN_WINDOW_HEIGHT tall, and at most MAX_WINDOW_SIDE a side whatever the
/// render size (the image is shown scaled; X11 takes no side above 65535,
/// and winit panics on one). A size no adapter renders is refused by the
/// session, as `render` refuses it.
pub fn attributes(options: &ViewOptions) -> WindowAttributes {
    let (w, h) = options.size;
    Window::default_attributes().with_title(format!("glint: {}", options.scene.display())).with_inner_size(winit::dpi::LogicalSize::new(
        (f64::from(w) + f64::from(PANEL_WIDTH)).min(MAX_WINDOW_SIDE),
        f64::from(h.max(MIN_WINDOW_HEIGHT)).min(MAX_WINDOW_SIDE),
    ))
}

/// An 8-bit, non-sRGB surface format: egui-wgpu and the present pass
/// encode sRGB themselves.
pub fn pick_format(caps: &wgpu::SurfaceCapabilities) -> Option<wgpu::TextureFormat> {
    let preferred = [wgpu::TextureFormat::Bgra8Unorm, wgpu::TextureFormat::Rgba8Unorm];
    preferred.into_iter().find(|f| caps.formats.contains(f)).or_else(|| caps.formats.iter().copied().find(|f| !f.is_srgb()))
}
