//! Plots drawn with plotters, with an embedded font (DejaVu Sans), so they need no system fonts.

use std::path::Path;
use std::sync::Once;

use anyhow::{anyhow, Result};
use plotters::prelude::*;
use plotters::style::FontStyle;

static FONT: Once = Once::new();

pub fn register_font() {
    FONT.call_once(|| {
        // The bytes are a valid TrueType font shipped by the `dejavu` crate; if registering
        // failed anyway, text would be missing from the plot, which `draw` then reports.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// Colours of the methods, in order.
const COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// Draws, for each input, the time of each step for each method (milliseconds), one panel per
/// input stacked vertically. `series[i] = (input name, per method: per step seconds)`.
pub fn step_times(
    path: &Path,
    methods: &[String],
    series: &[(String, Vec<Vec<f64>>)],
) -> Result<()> {
    register_font();
    let panel_height = 320u32;
    let height = panel_height * series.len().max(1) as u32;
    let root = BitMapBackend::new(path, (960, height)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| anyhow!("{}: cannot draw the plot: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let panels = root.split_evenly((series.len().max(1), 1));
    for (panel, (name, per_method)) in panels.iter().zip(series) {
        let steps = per_method.iter().map(Vec::len).max().unwrap_or(0).max(1);
        let top = per_method
            .iter()
            .flatten()
            .fold(0.0f64, |m, &s| m.max(s * 1e3))
            .max(1e-3)
            * 1.1;
        let mut chart = ChartBuilder::on(panel)
            .caption(format!("{name}: time per step"), ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.5f64..(steps as f64 - 0.5), 0f64..top)
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc("step")
            .x_labels(steps.min(12))
            .x_label_formatter(&|x| format!("{x:.0}"))
            .y_desc("milliseconds")
            .y_label_formatter(&|y| format!("{y:.0}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| err(&e))?;
        for (i, (method, values)) in methods.iter().zip(per_method).enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            chart
                .draw_series(LineSeries::new(
                    values.iter().enumerate().map(|(k, s)| (k as f64, s * 1e3)),
                    colour.stroke_width(2),
                ))
                .map_err(|e| err(&e))?
                .label(method.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
                });
            chart
                .draw_series(
                    values
                        .iter()
                        .enumerate()
                        .map(|(k, s)| Circle::new((k as f64, s * 1e3), 3, colour.filled())),
                )
                .map_err(|e| err(&e))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
