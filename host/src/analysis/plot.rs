//! Log–log line plots (error versus time) written as SVG and PNG with the same drawing code.
//! Text uses the embedded DejaVu Sans (`host/data/fonts/`), so plots look the same on every
//! machine and need no system fonts.

use super::AnalysisError;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

/// DejaVu Sans 2.37 (Bitstream Vera licence, see host/data/fonts/README.md).
static FONT: &[u8] = include_bytes!("../../data/fonts/DejaVuSans.ttf"); // host/data/fonts/DejaVuSans.ttf

/// One curve: a legend label and (x, y) points with x, y > 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points in data units (non-positive values are skipped: they have no logarithm).
    pub points: Vec<(f64, f64)>,
}

/// Axis titles and the plot title.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotLabels {
    /// Title above the plot.
    pub title: String,
    /// x-axis title.
    pub x: String,
    /// y-axis title.
    pub y: String,
}

/// Plot size in pixels (SVG user units and PNG pixels).
const SIZE: (u32, u32) = (900, 600);

/// Register the embedded font under "sans-serif", once (also used by the sensor maps).
pub(crate) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TrueType font (checked by the plot test); if registration
        // failed anyway, text drawing would report an error instead of panicking.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Decade-aligned log range covering `values` (with a little margin).
fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for v in values.filter(|v| *v > 0.0 && v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.1, 10.0);
    }
    if hi <= lo * 1.0001 {
        hi = lo * 10.0;
    }
    (lo / 1.3, hi * 1.3)
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    series: &[Series],
    labels: &PlotLabels,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let valid = |p: &&(f64, f64)| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite();
    let (x0, x1) = log_range(
        series
            .iter()
            .flat_map(|s| s.points.iter().filter(valid).map(|p| p.0)),
    );
    let (y0, y1) = log_range(
        series
            .iter()
            .flat_map(|s| s.points.iter().filter(valid).map(|p| p.1)),
    );
    let mut chart = ChartBuilder::on(&root)
        .caption(&labels.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc(&labels.x)
        .y_desc(&labels.y)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .x_label_formatter(&|v| format!("{v:.3}"))
        .y_label_formatter(&|v| format!("{v:.1e}"))
        .draw()
        .map_err(|e| e.to_string())?;
    for (i, s) in series.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        let pts: Vec<(f64, f64)> = s.points.iter().filter(valid).cloned().collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(&s.label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(2))
            });
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
            .map_err(|e| e.to_string())?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

/// Write the log–log plot of `series` to `svg` and `png`.
pub fn plot_loglog(
    series: &[Series],
    labels: &PlotLabels,
    svg: &Path,
    png: &Path,
) -> Result<(), AnalysisError> {
    register_font();
    let werr = |path: &Path, message: String| AnalysisError::Write {
        path: path.to_path_buf(),
        message,
    };
    let mut svg_text = String::new();
    draw(
        SVGBackend::with_string(&mut svg_text, SIZE).into_drawing_area(),
        series,
        labels,
    )
    .map_err(|e| werr(svg, e))?;
    std::fs::write(svg, svg_text).map_err(|e| werr(svg, e.to_string()))?;

    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(
        BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area(),
        series,
        labels,
    )
    .map_err(|e| werr(png, e))?;
    let file = std::fs::File::create(png).map_err(|e| werr(png, e.to_string()))?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), SIZE.0, SIZE.1);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(|e| werr(png, e.to_string()))?;
    w.write_image_data(&rgb)
        .map_err(|e| werr(png, e.to_string()))?;
    w.finish().map_err(|e| werr(png, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plot with two series is written as SVG (containing the legend text, so the font was
    /// usable) and as a PNG of the stated size that is not blank (some pixels are not white).
    #[test]
    fn writes_svg_and_png() {
        let dir = std::env::temp_dir().join(format!("spectrace-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let s = [
            Series {
                label: "pt (slope -0.50)".into(),
                points: vec![(0.1, 0.1), (0.4, 0.05), (1.6, 0.025)],
            },
            Series {
                label: "bdpt".into(),
                points: vec![(0.2, 0.08), (0.8, 0.04), (0.0, 1.0)],
            },
        ];
        let labels = PlotLabels {
            title: "t".into(),
            x: "time (s)".into(),
            y: "RMSE".into(),
        };
        let (svg, png) = (dir.join("p.svg"), dir.join("p.png"));
        plot_loglog(&s, &labels, &svg, &png).unwrap();
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("pt (slope -0.50)"));
        let decoder = png::Decoder::new(std::fs::File::open(&png).unwrap());
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), SIZE);
        assert!(buf.iter().any(|&b| b < 200));
        std::fs::remove_dir_all(&dir).ok();
    }
}
