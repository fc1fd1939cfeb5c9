//! `trade.png`: FLIP mean against cumulative time, both on log axes, one
//! curve per graph (or sweep setting), the Pareto front drawn over them in
//! black. Plotters with an embedded font (DejaVu Sans, assets/), so no
//! system font library is needed.

use std::path::Path;

use plotters::prelude::*;

use super::{pareto, Curve};

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// Draws the curves into a PNG at `path`.
pub fn draw(path: &Path, title: &str, curves: &[Curve]) -> Result<(), String> {
    // Registering twice (a second plot in one process) is harmless.
    let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    let points = || curves.iter().flat_map(|c| &c.samples).filter(|s| s.cum_ms > 0.0 && s.flip > 0.0);
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for s in points() {
        x0 = x0.min(s.cum_ms);
        x1 = x1.max(s.cum_ms);
        y0 = y0.min(s.flip);
        y1 = y1.max(s.flip);
    }
    if x0 > x1 {
        return Err("no frames to plot".into());
    }
    let (x0, x1, y0, y1) = (x0 * 0.8, x1 * 1.25, y0 * 0.8, (y1 * 1.25).min(1.0).max(y0 * 1.1));
    let (w, h) = (960u32, 640u32);
    let mut buffer = vec![0u8; (w * h * 3) as usize];
    draw_into(&mut buffer, (w, h), title, curves, (x0, x1, y0, y1))?;
    let image = image::RgbImage::from_raw(w, h, buffer).ok_or("the plot buffer has the wrong size")?;
    image.save(path).map_err(|e| e.to_string())
}

fn draw_into(buffer: &mut [u8], size: (u32, u32), title: &str, curves: &[Curve], (x0, x1, y0, y1): (f64, f64, f64, f64)) -> Result<(), String> {
    let root = BitMapBackend::with_buffer(buffer, size).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("cumulative time (ms)")
        .y_desc("FLIP mean against the reference")
        .label_style(("sans-serif", 14))
        .x_labels(6)
        .y_labels(12)
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_label_formatter(&|y| format!("{y:.2}"))
        .draw()
        .map_err(|e| e.to_string())?;
    for (i, c) in curves.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let series = c.samples.iter().filter(|s| s.cum_ms > 0.0 && s.flip > 0.0).map(|s| (s.cum_ms, s.flip));
        chart
            .draw_series(LineSeries::new(series, colour.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(c.label())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    let front: Vec<(f64, f64)> = pareto(curves).iter().filter(|s| s.cum_ms > 0.0 && s.flip > 0.0).map(|s| (s.cum_ms, s.flip)).collect();
    chart
        .draw_series(LineSeries::new(front.iter().copied(), BLACK.stroke_width(1)))
        .map_err(|e| e.to_string())?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(1)));
    chart
        .draw_series(front.iter().map(|&p| Circle::new(p, 3, BLACK.filled())))
        .map_err(|e| e.to_string())?;
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

/// One column of `compare.png`: a label, an sRGB8 image and, for a graph,
/// its FLIP map against the reference (magma) and FLIP mean.
pub struct Panel {
    /// The caption.
    pub label: String,
    /// The image, sRGB8 RGB at the panel size.
    pub image: Vec<u8>,
    /// The FLIP map (magma, sRGB8 RGB) and FLIP mean, for a graph.
    pub flip_map: Option<(Vec<u8>, f64)>,
}

/// `compare.png`: the reference and each graph's final image side by side,
/// each graph's FLIP map under it, labelled. Images are `size` each.
pub fn compare(path: &Path, size: (u32, u32), panels: &[Panel]) -> Result<(), String> {
    let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    let (w, h) = size;
    let (label_h, gap) = (28u32, 8u32);
    let width = panels.len() as u32 * (w + gap) + gap;
    let height = label_h + 2 * h + 3 * gap + label_h;
    let mut buffer = vec![255u8; (width * height * 3) as usize];
    let mut blit = |rgb: &[u8], x0: u32, y0: u32| {
        for y in 0..h {
            for x in 0..w {
                let s = ((y * w + x) * 3) as usize;
                let d = (((y0 + y) * width + x0 + x) * 3) as usize;
                if let (Some(src), Some(dst)) = (rgb.get(s..s + 3), buffer.get_mut(d..d + 3)) {
                    dst.copy_from_slice(src);
                }
            }
        }
    };
    for (i, p) in panels.iter().enumerate() {
        let x = gap + i as u32 * (w + gap);
        blit(&p.image, x, label_h);
        if let Some((map, _)) = &p.flip_map {
            blit(map, x, label_h + h + gap + label_h);
        }
    }
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (width, height)).into_drawing_area();
        let style = ("sans-serif", 15).into_font().color(&BLACK);
        for (i, p) in panels.iter().enumerate() {
            let x = (gap + i as u32 * (w + gap)) as i32;
            root.draw_text(&p.label, &style, (x, 6)).map_err(|e| e.to_string())?;
            if let Some((_, mean)) = &p.flip_map {
                root.draw_text(&format!("FLIP {mean:.4}"), &style, (x, (label_h + h + gap + 6) as i32)).map_err(|e| e.to_string())?;
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    let image = image::RgbImage::from_raw(width, height, buffer).ok_or("the comparison buffer has the wrong size")?;
    image.save(path).map_err(|e| e.to_string())
}
