//! `cargo xtask figures`, Catmull-Clark part: the experiment of Settgast et al. 2004, Section 5,
//! on the paper's test scene (Fig. 12; here 40 instances of `catmark_helmet`) with the camera
//! orbiting the scene centre. Runs `subdiv bench framerate` and writes CSV, PNG and SVG plots into
//! `docs/figures/` and a section of `docs/figures.md`:
//! Fig. 5 (triangles per frame, adaptive vs uniform depths 2, 3, 4), Fig. 6 (patches per depth per
//! frame), Fig. 7 (frames per second: fixed depths 2, 3, 4 and adaptive with frame-rate control
//! whose target switches half-way, rendered headless on the Vulkan driver).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, bail};
use plotters::prelude::*;

const BEGIN: &str = "<!-- figures:cc:begin -->";
const END: &str = "<!-- figures:cc:end -->";

/// One line of `subdiv bench framerate`.
#[derive(Clone, Debug, Default)]
struct Frame {
    fps: f64,
    triangles: u64,
    maxsd: u32,
    patches: Vec<u64>,
}

fn bench(exe: &Path, args: &[&str]) -> Result<Vec<Frame>> {
    let spinner = crate::spinner(format!("subdiv bench framerate {}", args.join(" ")));
    let out = Command::new(exe)
        .args(["bench", "framerate"])
        .args(args)
        .output();
    spinner.finish_and_clear();
    let out = out.context("running subdiv bench framerate")?;
    if !out.status.success() {
        bail!(
            "subdiv bench framerate {args:?} failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let mut frames = Vec::new();
    for line in String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| l.starts_with("frame="))
    {
        let mut f = Frame::default();
        for kv in line.split_whitespace() {
            let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
            match k {
                "fps" => f.fps = v.parse()?,
                "triangles" => f.triangles = v.parse()?,
                "maxsd" => f.maxsd = v.parse()?,
                "patches" => {
                    f.patches = v
                        .split(',')
                        .filter(|x| !x.is_empty())
                        .map(|x| x.parse())
                        .collect::<Result<_, _>>()?
                }
                _ => {}
            }
        }
        frames.push(f);
    }
    Ok(frames)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Plot size in pixels (PNG) and units (SVG).
const PLOT_SIZE: (u32, u32) = (900, 500);

/// Writes the plot as `STEM.png` (rasterised, text with the DejaVu Sans font) and `STEM.svg`.
fn plot(stem: &Path, title: &str, y_label: &str, series: &[(String, Vec<f64>)]) -> Result<()> {
    let svg = stem.with_extension("svg");
    draw(
        SVGBackend::new(&svg, PLOT_SIZE).into_drawing_area(),
        title,
        y_label,
        series,
    )
    .with_context(|| format!("drawing {}", svg.display()))?;
    let (w, h) = PLOT_SIZE;
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    draw(
        BitMapBackend::with_buffer(&mut rgb, PLOT_SIZE).into_drawing_area(),
        title,
        y_label,
        series,
    )
    .with_context(|| format!("drawing {}", stem.display()))?;
    let png = stem.with_extension("png");
    image::save_buffer(&png, &rgb, w, h, image::ExtendedColorType::Rgb8)
        .with_context(|| format!("writing {}", png.display()))?;
    Ok(())
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    y_label: &str,
    series: &[(String, Vec<f64>)],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let n = series.iter().map(|s| s.1.len()).max().unwrap_or(1);
    let ymax = series
        .iter()
        .flat_map(|s| s.1.iter().copied())
        .fold(0.0f64, f64::max)
        * 1.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(0f64..n as f64, 0f64..ymax.max(1.0))?;
    chart
        .configure_mesh()
        .x_desc("frame")
        .y_desc(y_label)
        .draw()?;
    let palette = [RED, BLUE, GREEN, MAGENTA, CYAN, BLACK];
    for (k, (name, ys)) in series.iter().enumerate() {
        let c = palette[k % palette.len()];
        chart
            .draw_series(LineSeries::new(
                ys.iter().enumerate().map(|(i, &y)| (i as f64, y)),
                c.stroke_width(2),
            ))?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// DejaVu Sans, the font the plots' text is rasterised with (Debian package `fonts-dejavu-core`).
const FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Registers the plots' font with plotters: installs it with apt when missing and running as
/// root, otherwise names the command and fails.
pub(crate) fn register_font() -> Result<()> {
    if !Path::new(FONT).exists() {
        let cmd = "apt-get update && apt-get install -y fonts-dejavu-core";
        if !crate::vulkan::is_root() {
            bail!(
                "the plots need the DejaVu Sans font ({FONT}). Install it with:\n    sudo sh -c '{cmd}'\nthen run this command again"
            );
        }
        eprintln!("figures: installing the plot font: {cmd}");
        let status = Command::new("sh")
            .args(["-c", cmd])
            .env("DEBIAN_FRONTEND", "noninteractive")
            .status()
            .context("could not run apt-get")?;
        if !status.success() || !Path::new(FONT).exists() {
            bail!("installing fonts-dejavu-core failed ({status}); run as root: {cmd}");
        }
    }
    let bytes: &'static [u8] = Box::leak(
        std::fs::read(FONT)
            .with_context(|| format!("reading {FONT}"))?
            .into_boxed_slice(),
    );
    plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
        .map_err(|_| anyhow::anyhow!("{FONT} is not a font plotters can read"))?;
    Ok(())
}

fn csv(path: &Path, header: &str, cols: &[Vec<f64>]) -> Result<()> {
    let n = cols.iter().map(|c| c.len()).max().unwrap_or(0);
    let mut s = format!("frame,{header}\n");
    for i in 0..n {
        let row: Vec<String> = cols
            .iter()
            .map(|c| c.get(i).map(|v| format!("{v}")).unwrap_or_default())
            .collect();
        writeln!(s, "{i},{}", row.join(","))?;
    }
    std::fs::write(path, s).with_context(|| format!("writing {}", path.display()))
}

/// Runs the experiment with the release `subdiv` binary `exe` and writes the figures.
pub fn run(root: &Path, exe: &Path) -> Result<()> {
    let dir: PathBuf = root.join("docs/figures");
    std::fs::create_dir_all(&dir)?;
    register_font()?;
    let frames = "180";
    // Figs. 5 and 6: tessellation only, along the orbit.
    let adaptive = bench(exe, &["--no-render", "--frames", frames])?;
    let uniform: Vec<(u8, u64)> = [2u8, 3, 4]
        .iter()
        .map(|&d| {
            Ok((
                d,
                bench(
                    exe,
                    &["--no-render", "--frames", "1", "--depth", &d.to_string()],
                )?[0]
                    .triangles,
            ))
        })
        .collect::<Result<_>>()?;
    let tri: Vec<f64> = adaptive.iter().map(|f| f.triangles as f64).collect();
    let mut series = vec![("adaptive (depths 0-4)".to_string(), tri.clone())];
    for &(d, t) in &uniform {
        series.push((format!("uniform depth {d}"), vec![t as f64; tri.len()]));
    }
    plot(
        &dir.join("fig5_triangles"),
        "Fig. 5: triangles per frame (40 helmets, orbit)",
        "triangles",
        &series,
    )?;
    csv(
        &dir.join("fig5_triangles.csv"),
        "adaptive,uniform2,uniform3,uniform4",
        &series.iter().map(|s| s.1.clone()).collect::<Vec<_>>(),
    )?;
    let depths = adaptive.iter().map(|f| f.patches.len()).max().unwrap_or(0);
    let per_depth: Vec<(String, Vec<f64>)> = (0..depths)
        .map(|d| {
            (
                format!("depth {d}"),
                adaptive
                    .iter()
                    .map(|f| *f.patches.get(d).unwrap_or(&0) as f64)
                    .collect(),
            )
        })
        .collect();
    plot(
        &dir.join("fig6_patches"),
        "Fig. 6: patches per depth per frame",
        "patches",
        &per_depth,
    )?;
    let hdr: Vec<String> = (0..depths).map(|d| format!("depth{d}")).collect();
    csv(
        &dir.join("fig6_patches.csv"),
        &hdr.join(","),
        &per_depth.iter().map(|s| s.1.clone()).collect::<Vec<_>>(),
    )?;

    // Fig. 7: rendered frame rates (lavapipe).
    let fixed: Vec<(u8, Vec<Frame>)> = [2u8, 3, 4]
        .iter()
        .map(|&d| {
            Ok((
                d,
                bench(exe, &["--frames", "100", "--depth", &d.to_string()])?,
            ))
        })
        .collect::<Result<_>>()?;
    let fps_of = |d: u8| {
        median(
            fixed
                .iter()
                .find(|x| x.0 == d)
                .map(|x| x.1.iter().skip(1).map(|f| f.fps).collect())
                .unwrap_or(vec![0.0]),
        )
    };
    let (f2, f3, f4) = (fps_of(2), fps_of(3), fps_of(4));
    // Targets between the fixed depths, as in the paper (14-15 -> 39-40 fps between 7, 17, 31).
    let (t_low, t_high) = ((f3 + f4) / 2.0, (f2 + f3) / 2.0);
    let ctl = bench(
        exe,
        &[
            "--frames",
            "160",
            "--target-fps",
            &format!("{t_low:.2}"),
            "--switch-fps",
            &format!("{t_high:.2}"),
        ],
    )?;
    let mut s7: Vec<(String, Vec<f64>)> = fixed
        .iter()
        .map(|(d, fr)| {
            (
                format!("uniform depth {d}"),
                fr.iter().map(|f| f.fps).collect(),
            )
        })
        .collect();
    s7.push((
        format!("adaptive, target {t_low:.1} then {t_high:.1} fps"),
        ctl.iter().map(|f| f.fps).collect(),
    ));
    plot(
        &dir.join("fig7_framerate"),
        "Fig. 7: frames per second (lavapipe)",
        "fps",
        &s7,
    )?;
    csv(
        &dir.join("fig7_framerate.csv"),
        "uniform2,uniform3,uniform4,adaptive",
        &s7.iter().map(|s| s.1.clone()).collect::<Vec<_>>(),
    )?;
    // Frames after the switch until the rate stays within 10 % of the target.
    let half = ctl.len() / 2;
    let settle = (half..ctl.len())
        .find(|&i| {
            ctl[i..]
                .iter()
                .all(|f| (f.fps / t_high - 1.0).abs() <= 0.10)
        })
        .map(|i| i - half);
    let settle_low = (1..half).find(|&i| {
        ctl[i..half]
            .iter()
            .all(|f| (f.fps / t_low - 1.0).abs() <= 0.10)
    });

    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let mut md = String::new();
    writeln!(md, "{BEGIN}")?;
    writeln!(
        md,
        "## Adaptive Catmull-Clark tessellation (Settgast et al. 2004, Figs. 5–7)\n"
    )?;
    writeln!(
        md,
        "Generated by `cargo xtask figures` (data: `subdiv bench framerate`, scene: 40 instances of"
    )?;
    writeln!(
        md,
        "`catmark_helmet`, 2320 cage faces, camera orbiting the scene centre 2° per frame, 640×480,"
    )?;
    writeln!(
        md,
        "depths 0–4). Plots as PNG (and the same as SVG beside them: `docs/figures/*.svg`), data as CSV.\n"
    )?;
    writeln!(md, "![Fig. 5](figures/fig5_triangles.png)\n")?;
    writeln!(
        md,
        "**Fig. 5** Triangles per frame: adaptive {:.0} on average (min {:.0}, max {:.0}) against uniform depth 2: {}, 3: {}, 4: {} \
         (the uniform counts include the back faces). The adaptive count is {:.1} % of uniform depth 4.\n",
        mean(&tri),
        tri.iter().copied().fold(f64::INFINITY, f64::min),
        tri.iter().copied().fold(0.0, f64::max),
        uniform[0].1,
        uniform[1].1,
        uniform[2].1,
        100.0 * mean(&tri) / uniform[2].1 as f64
    )?;
    writeln!(md, "![Fig. 6](figures/fig6_patches.png)\n")?;
    let avg_pd: Vec<String> = per_depth
        .iter()
        .map(|(n, v)| format!("{n}: {:.0}", mean(v)))
        .collect();
    writeln!(
        md,
        "**Fig. 6** Patches per depth per frame (average {}). As in the paper, most patches stay coarse (back faces at depth 0) while silhouettes and near, curved regions go deep.\n",
        avg_pd.join(", ")
    )?;
    writeln!(md, "![Fig. 7](figures/fig7_framerate.png)\n")?;
    writeln!(
        md,
        "**Fig. 7** Frames per second on lavapipe (CPU Vulkan, 2 cores; tessellation + rendering): uniform depth 2: {f2:.1}, 3: {f3:.1}, 4: {f4:.1} fps \
         (paper, GeForce 4: 31, 17, 7). Adaptive with frame-rate control, target {t_low:.1} fps for 80 frames then {t_high:.1} fps: {}; {}.\n",
        match settle_low {
            Some(i) => format!("within 10 % of the first target from frame {i} on"),
            None => "the first target is not held within 10 % (the adaptive tessellation alone is faster than the target, and the cap cannot add detail beyond depth 4)".to_string(),
        },
        match settle {
            Some(i) => format!("within 10 % of the second target {i} frames after the switch (the paper: within 70 frames)"),
            None => "the second target is not reached within 10 % by the end of the run".to_string(),
        }
    )?;
    writeln!(md, "{END}")?;
    let path = root.join("docs/figures.md");
    let old = std::fs::read_to_string(&path).unwrap_or_else(|_| "# Figures\n".to_string());
    let new = match (old.find(BEGIN), old.find(END)) {
        (Some(b), Some(e)) if e > b => {
            format!("{}{}{}", &old[..b], md.trim_end(), &old[e + END.len()..])
        }
        _ => format!("{}\n\n{}", old.trim_end(), md),
    };
    std::fs::write(&path, new)?;
    println!(
        "figures: wrote docs/figures/fig5_triangles, fig6_patches, fig7_framerate (.png, .svg, .csv) and docs/figures.md"
    );
    Ok(())
}
