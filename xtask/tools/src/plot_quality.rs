//! `cargo xtask plot-quality [--shading] STEM LABEL=FILE...`: plots triangles against the largest
//! silhouette error (or, with `--shading`, the 99th percentile of the shading angle) per
//! configuration from saved `subdiv bench quality` output (one run per `LABEL=FILE`), as
//! `STEM.png`, `STEM.svg` and `STEM.csv` (docs/performance.md, "Image quality against the true
//! surface").

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use plotters::prelude::*;

/// One `config=...` line of `subdiv bench quality`.
#[derive(Clone, Debug)]
struct Row {
    config: String,
    triangles: f64,
    silhouette_max: f64,
    shading_p99: f64,
}

/// Which error the plot's vertical axis shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Metric {
    /// `silhouette_px_max`.
    Silhouette,
    /// `shading_deg_p99`.
    Shading,
}

impl Metric {
    fn of(self, r: &Row) -> f64 {
        match self {
            Metric::Silhouette => r.silhouette_max,
            Metric::Shading => r.shading_p99,
        }
    }
    /// Errors below this are drawn at it (log axis).
    fn floor(self) -> f64 {
        match self {
            Metric::Silhouette => 0.1,
            Metric::Shading => 0.01,
        }
    }
    fn caption(self) -> &'static str {
        match self {
            Metric::Silhouette => {
                "Triangles against largest silhouette error (vs. reference depth maxsd+1)"
            }
            Metric::Shading => {
                "Triangles against shading error, 99th percentile (vs. reference depth maxsd+1)"
            }
        }
    }
    fn axis(self) -> &'static str {
        match self {
            Metric::Silhouette => "silhouette_px_max (px)",
            Metric::Shading => "shading_deg_p99 (degrees)",
        }
    }
    fn column(self) -> &'static str {
        match self {
            Metric::Silhouette => "silhouette_px_max",
            Metric::Shading => "shading_deg_p99",
        }
    }
}

/// One run: its label and rows.
struct Run {
    label: String,
    rows: Vec<Row>,
}

fn parse(label: &str, path: &Path) -> Result<Run> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut rows = Vec::new();
    for line in text.lines().filter(|l| l.starts_with("config=")) {
        let mut row = Row {
            config: String::new(),
            triangles: f64::NAN,
            silhouette_max: f64::NAN,
            shading_p99: f64::NAN,
        };
        for kv in line.split_whitespace() {
            match kv.split_once('=') {
                Some(("config", v)) => row.config = v.to_string(),
                Some(("triangles", v)) => row.triangles = v.parse()?,
                Some(("silhouette_px_max", v)) => row.silhouette_max = v.parse()?,
                Some(("shading_deg_p99", v)) => row.shading_p99 = v.parse()?,
                _ => {}
            }
        }
        rows.push(row);
    }
    if rows.is_empty() {
        bail!("{}: no `config=` lines", path.display());
    }
    Ok(Run {
        label: label.to_string(),
        rows,
    })
}

/// Plot size in pixels (PNG) and units (SVG).
const PLOT_SIZE: (u32, u32) = (900, 560);

/// Short names of the adaptive configurations next to their markers.
fn short(config: &str) -> String {
    match config {
        "curvature" => "curv".to_string(),
        c => c.replace("pixel-error-", "pe"),
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    runs: &[Run],
    metric: Metric,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let rows = runs.iter().flat_map(|r| r.rows.iter());
    let (tmin, tmax, emax) = rows.fold((f64::MAX, 1.0f64, 1.0f64), |(a, b, c), r| {
        (a.min(r.triangles), b.max(r.triangles), c.max(metric.of(r)))
    });
    let mut chart = ChartBuilder::on(&root)
        .caption(metric.caption(), ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (tmin.max(1.0) / 1.5..tmax * 1.5).log_scale(),
            (metric.floor()..emax * 1.5).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("triangles drawn")
        .y_desc(metric.axis())
        .draw()?;
    let palette = [RED, BLUE, GREEN, MAGENTA, BLACK];
    for (k, run) in runs.iter().enumerate() {
        let c = palette[k % palette.len()];
        let point = |r: &Row| (r.triangles.max(1.0), metric.of(r).max(metric.floor()));
        let uniform: Vec<(f64, f64)> = run
            .rows
            .iter()
            .filter(|r| r.config.starts_with("uniform-"))
            .map(point)
            .collect();
        chart
            .draw_series(LineSeries::new(uniform.clone(), c.stroke_width(2)))?
            .label(format!("{}: uniform 0..maxsd (circles)", run.label))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
        chart.draw_series(uniform.iter().map(|&p| Circle::new(p, 4, c.filled())))?;
        chart.draw_series(
            run.rows
                .iter()
                .filter(|r| !r.config.starts_with("uniform-"))
                .map(|r| {
                    let p = point(r);
                    EmptyElement::at(p)
                        + TriangleMarker::new((0, 0), 6, c.filled())
                        + Text::new(
                            short(&r.config),
                            (6, -14),
                            ("sans-serif", 13).into_font().color(&c),
                        )
                }),
        )?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

fn csv(path: &Path, runs: &[Run], metric: Metric) -> Result<()> {
    let mut s = format!("run,config,triangles,{}\n", metric.column());
    for run in runs {
        for r in &run.rows {
            writeln!(
                s,
                "{},{},{},{}",
                run.label,
                r.config,
                r.triangles,
                metric.of(r)
            )?;
        }
    }
    std::fs::write(path, s).with_context(|| format!("writing {}", path.display()))
}

/// `args`: `[--shading] STEM LABEL=FILE...`.
pub fn run(args: &[String]) -> Result<()> {
    const USAGE: &str = "usage: cargo xtask plot-quality [--shading] STEM LABEL=FILE...";
    let (metric, args) = match args.split_first() {
        Some((flag, rest)) if flag == "--shading" => (Metric::Shading, rest),
        _ => (Metric::Silhouette, args),
    };
    let Some((stem, specs)) = args.split_first() else {
        bail!(USAGE);
    };
    if specs.is_empty() {
        bail!(USAGE);
    }
    let runs = specs
        .iter()
        .map(|s| {
            let (label, file) = s
                .split_once('=')
                .with_context(|| format!("'{s}' is not LABEL=FILE"))?;
            parse(label, Path::new(file))
        })
        .collect::<Result<Vec<_>>>()?;
    crate::figures_cc::register_font()?;
    let stem = PathBuf::from(stem);
    let svg = stem.with_extension("svg");
    draw(
        SVGBackend::new(&svg, PLOT_SIZE).into_drawing_area(),
        &runs,
        metric,
    )
    .with_context(|| format!("drawing {}", svg.display()))?;
    let (w, h) = PLOT_SIZE;
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    draw(
        BitMapBackend::with_buffer(&mut rgb, PLOT_SIZE).into_drawing_area(),
        &runs,
        metric,
    )
    .with_context(|| format!("drawing {}", stem.display()))?;
    let png = stem.with_extension("png");
    image::save_buffer(&png, &rgb, w, h, image::ExtendedColorType::Rgb8)
        .with_context(|| format!("writing {}", png.display()))?;
    csv(&stem.with_extension("csv"), &runs, metric)?;
    println!("plot-quality: wrote {} (.svg, .csv)", png.display());
    Ok(())
}
