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

/// Colours of the phases, by name (pipeline order).
const PHASES: [(&str, RGBColor); 5] = [
    ("clustering", RGBColor(255, 127, 14)),
    ("merging", RGBColor(188, 189, 34)),
    ("build", RGBColor(23, 190, 207)),
    ("traverse", RGBColor(127, 127, 127)),
    ("narrow", RGBColor(140, 86, 75)),
];

fn phase_colour(name: &str) -> RGBColor {
    PHASES
        .iter()
        .find(|p| p.0 == name)
        .map_or(RGBColor(0, 0, 0), |p| p.1)
}

/// One input's figures for [`step_times`].
pub struct PlotInput {
    /// The input's name.
    pub name: String,
    /// Per method: the seconds of each step.
    pub per_step: Vec<Vec<f64>>,
    /// Per method: the average seconds per step of each phase, in pipeline order.
    pub phases: Vec<Vec<(&'static str, f64)>>,
}

/// Width of the legend strip right of each chart, in pixels: legends go there, never over
/// the data.
const LEGEND_WIDTH: i32 = 130;

/// Draws a legend (colour, label, line or box) in the strip at the right of `area`.
fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    entries: &[(RGBColor, String, bool)],
) -> Result<(), String> {
    let (w, _) = area.dim_in_pixel();
    let x = w as i32 - LEGEND_WIDTH + 8;
    let mut y = 40;
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    area.draw_text(title, &("sans-serif", 13).into_font().color(&BLACK), (x, y))
        .map_err(e)?;
    y += 20;
    for (colour, label, line) in entries {
        if *line {
            area.draw(&PathElement::new(
                vec![(x, y + 7), (x + 18, y + 7)],
                colour.stroke_width(2),
            ))
            .map_err(e)?;
            area.draw(&Circle::new((x + 9, y + 7), 3, colour.filled()))
                .map_err(e)?;
        } else {
            area.draw(&Rectangle::new(
                [(x, y + 1), (x + 14, y + 13)],
                colour.filled(),
            ))
            .map_err(e)?;
        }
        area.draw_text(
            label,
            &("sans-serif", 13).into_font().color(&BLACK),
            (x + 24, y),
        )
        .map_err(e)?;
        y += 20;
    }
    Ok(())
}

/// Draws, for each input, one panel of two charts side by side: the time of each step for
/// each method (milliseconds; lines and points, or labelled bars for a one-step input), and
/// where the time goes: per method, the average milliseconds per step of each phase
/// (clustering, merging, build, traverse, narrow) stacked. Legends sit in a strip right of
/// each chart, so they cover no data.
pub fn step_times(path: &Path, methods: &[String], inputs: &[PlotInput]) -> Result<()> {
    register_font();
    let panel_height = 340u32;
    let height = panel_height * inputs.len().max(1) as u32;
    let root = BitMapBackend::new(path, (1280, height)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| anyhow!("{}: cannot draw the plot: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let panels = root.split_evenly((inputs.len().max(1), 1));
    let name_of = |i: usize| methods.get(i).cloned().unwrap_or_default();
    for (panel, input) in panels.iter().zip(inputs) {
        let (left, right) = panel.split_horizontally(760);
        // Time per step.
        let per_method = &input.per_step;
        let steps = per_method.iter().map(Vec::len).max().unwrap_or(0).max(1);
        let top = per_method
            .iter()
            .flatten()
            .fold(0.0f64, |m, &s| m.max(s * 1e3))
            .max(1e-3)
            * 1.15;
        let one = steps == 1;
        let caption = if one {
            format!("{}: time of its one step", input.name)
        } else {
            format!("{}: time per step", input.name)
        };
        let x_range = if one {
            -0.5f64..(methods.len().max(1) as f64 - 0.5)
        } else {
            -0.5f64..(steps as f64 - 0.5)
        };
        let mut chart = ChartBuilder::on(&left)
            .caption(caption, ("sans-serif", 17))
            .margin(12)
            .margin_right(LEGEND_WIDTH as u32)
            .x_label_area_size(36)
            .y_label_area_size(60)
            .build_cartesian_2d(x_range, 0f64..top)
            .map_err(|e| err(&e))?;
        let method_label = |x: &f64| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 {
                name_of(i as usize)
            } else {
                String::new()
            }
        };
        let step_label = |x: &f64| format!("{x:.0}");
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_desc(if one { "method" } else { "step" })
            .x_labels(if one {
                methods.len() * 2 + 1
            } else {
                steps.min(12)
            })
            .x_label_formatter(if one { &method_label } else { &step_label })
            .y_desc("milliseconds")
            .y_label_formatter(&|y| format!("{y:.0}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| err(&e))?;
        for (i, values) in per_method.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            if one {
                let v = values.first().copied().unwrap_or(0.0) * 1e3;
                let x = i as f64;
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(x - 0.3, 0.0), (x + 0.3, v)],
                        colour.filled(),
                    )))
                    .map_err(|e| err(&e))?;
                chart
                    .draw_series(std::iter::once(Text::new(
                        format!("{v:.1} ms"),
                        (x - 0.2, v + top * 0.06),
                        ("sans-serif", 13).into_font(),
                    )))
                    .map_err(|e| err(&e))?;
            } else {
                chart
                    .draw_series(LineSeries::new(
                        values.iter().enumerate().map(|(k, s)| (k as f64, s * 1e3)),
                        colour.stroke_width(2),
                    ))
                    .map_err(|e| err(&e))?;
                chart
                    .draw_series(
                        values
                            .iter()
                            .enumerate()
                            .map(|(k, s)| Circle::new((k as f64, s * 1e3), 3, colour.filled())),
                    )
                    .map_err(|e| err(&e))?;
            }
        }
        let entries: Vec<(RGBColor, String, bool)> = (0..per_method.len())
            .map(|i| (COLOURS[i % COLOURS.len()], name_of(i), !one))
            .collect();
        legend(&left, "method", &entries).map_err(|e| err(&e))?;

        // Where the time goes: stacked phases per method.
        let totals: Vec<f64> = input
            .phases
            .iter()
            .map(|p| p.iter().map(|x| x.1 * 1e3).sum())
            .collect();
        let top = totals.iter().copied().fold(1e-3, f64::max) * 1.15;
        let mut chart = ChartBuilder::on(&right)
            .caption("where the time goes (average per step)", ("sans-serif", 17))
            .margin(12)
            .margin_right(LEGEND_WIDTH as u32)
            .x_label_area_size(36)
            .y_label_area_size(60)
            .build_cartesian_2d(-0.5f64..(methods.len().max(1) as f64 - 0.5), 0f64..top)
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_desc("method")
            .x_labels(methods.len() * 2 + 1)
            .x_label_formatter(&method_label)
            .y_desc("milliseconds")
            .y_label_formatter(&|y| format!("{y:.0}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| err(&e))?;
        let mut seen: Vec<&'static str> = Vec::new();
        for (i, phases) in input.phases.iter().enumerate() {
            let x = i as f64;
            let mut base = 0.0;
            for &(name, seconds) in phases {
                let v = seconds * 1e3;
                chart
                    .draw_series(std::iter::once(Rectangle::new(
                        [(x - 0.3, base), (x + 0.3, base + v)],
                        phase_colour(name).filled(),
                    )))
                    .map_err(|e| err(&e))?;
                base += v;
                if !seen.contains(&name) {
                    seen.push(name);
                }
            }
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("{base:.1} ms"),
                    (x - 0.2, base + top * 0.06),
                    ("sans-serif", 13).into_font(),
                )))
                .map_err(|e| err(&e))?;
        }
        // Phases in pipeline order, as the bars stack them from the bottom.
        let entries: Vec<(RGBColor, String, bool)> = PHASES
            .iter()
            .filter(|p| seen.contains(&p.0))
            .rev()
            .map(|p| (p.1, p.0.to_string(), false))
            .collect();
        legend(&right, "phase", &entries).map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
