//! `cargo xtask figures`, Catmull-Clark part: the experiment of Settgast et al. 2004, Section 5,
//! on the paper's test scene (Fig. 12; here 40 instances of `catmark_helmet`) with the camera
//! orbiting the scene centre. Runs `subdiv bench framerate` and writes the data as CSV and the
//! plots as PNG and SVG into `docs/figures/`; the section of `docs/figures.md` is generated from
//! the CSV files by `figures_cc_text.rs`:
//! Fig. 5 (triangles per frame, adaptive vs uniform depths 2, 3, 4, and their image error against
//! the true surface every [`ERROR_EVERY`]th frame), Fig. 6 (quads per depth per frame), Fig. 7
//! (frames per second: uniform depths 2, 3, 4, adaptive without control, and the paper's
//! scenario — [`PAPER_TARGETS`], 14–15 then 39–40 fps — under the predictive controller and the
//! paper's side by side; then the predictive controller held at uniform depth 2's and 3's rates,
//! whose pictures are measured against uniform depths 3 and 4; rendered headless on the Vulkan
//! driver). Figures are measured on an idle machine: above a 1-minute load of [`MAX_LOAD`] the
//! run is refused unless forced, and then the text says so.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use plotters::prelude::*;

use crate::figures_cc_text::{CcData, UNIFORM, median};
use crate::figures_table::Table;

/// Frame size, camera step and adaptive depths of every run (`subdiv bench framerate`'s
/// defaults, passed explicitly so `cc_run.csv` states what was run).
const SIZE: &str = "640x480";
/// Samples per pixel of the rendered runs: one, as the paper's renderer drew (the viewer's and
/// `bench framerate`'s default is 4 where the device has it; lavapipe's 4 about halve the rate).
const SAMPLES: &str = "1";
const ORBIT_STEP_DEG: &str = "2";
const MAX_DEPTH: &str = "4";
/// The true surface of the error measurement: one level deeper than the adaptive maximum.
const REFERENCE_DEPTH: &str = "5";
/// Frames of the Fig. 5/6 runs: one full orbit at 2° per frame.
const FRAMES_TESSELLATION: usize = 180;
/// Frames of the Fig. 7 runs; the controlled run switches targets at half.
const FRAMES_RENDERED: usize = 200;
/// Image error of every `ERROR_EVERY`th frame.
const ERROR_EVERY: usize = 10;
/// Image size of the error renders (each at 3x3 samples per pixel).
const ERROR_SIZE: (u32, u32) = (640, 480);
/// The paper's scenario (Section 5): "from a given frame rate of 14 – 15 fps to 39 – 40 fps".
pub const PAPER_TARGETS: (f64, f64) = (15.0, 40.0);
/// The highest 1-minute load average the figures are measured under without `--force`.
pub const MAX_LOAD: f64 = 1.5;

/// The 1-minute load average (`/proc/loadavg`), 0 where it cannot be read: the machine is
/// shared, and the figures state the load they were measured under.
fn load_average() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse().ok())
        .unwrap_or(0.0)
}

/// One line of `subdiv bench framerate`.
#[derive(Clone, Debug, Default)]
struct Frame {
    frame: usize,
    fps: f64,
    triangles: u64,
    maxsd: u32,
    share: f64,
    predicted_ms: f64,
    quads: Vec<u64>,
    /// `silhouette_px_max`, `silhouette_px_p99`, `shading_deg_p99` of measured frames.
    error: Option<[f64; 3]>,
}

fn parse_line(line: &str) -> Result<Frame> {
    let mut f = Frame::default();
    let mut e = [f64::NAN; 3];
    for kv in line.split_whitespace() {
        let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
        let num = || {
            v.parse::<f64>()
                .with_context(|| format!("{k}={v} in {line:?}"))
        };
        match k {
            "frame" => f.frame = num()? as usize,
            "fps" => f.fps = num()?,
            "triangles" => f.triangles = num()? as u64,
            "maxsd" => f.maxsd = num()? as u32,
            "share" => f.share = num()?,
            "predicted_ms" => f.predicted_ms = num()?,
            "quads" => {
                f.quads = v
                    .split(',')
                    .filter(|x| !x.is_empty())
                    .map(|x| x.parse())
                    .collect::<Result<_, _>>()?
            }
            "silhouette_px_max" => e[0] = num()?,
            "silhouette_px_p99" => e[1] = num()?,
            "shading_deg_p99" => e[2] = num()?,
            _ => {}
        }
    }
    if e.iter().all(|x| x.is_finite()) {
        f.error = Some(e);
    }
    Ok(f)
}

fn bench(exe: &Path, args: &[&str]) -> Result<Vec<Frame>> {
    let common = [
        "--size",
        SIZE,
        "--orbit-step",
        ORBIT_STEP_DEG,
        "--max-depth",
        MAX_DEPTH,
        "--samples",
        SAMPLES,
    ];
    let spinner = crate::spinner(format!(
        "subdiv bench framerate {} {}",
        common.join(" "),
        args.join(" ")
    ));
    let out = Command::new(exe)
        .args(["bench", "framerate"])
        .args(common)
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
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter(|l| l.starts_with("frame="))
        .map(parse_line)
        .collect()
}

/// One plotted curve: its name and (x, y) points.
type Series = (String, Vec<(f64, f64)>);

fn per_frame(name: &str, ys: &[f64]) -> Series {
    (
        name.to_string(),
        ys.iter().enumerate().map(|(i, &y)| (i as f64, y)).collect(),
    )
}

/// Plot size in pixels (PNG) and units (SVG).
const PLOT_SIZE: (u32, u32) = (900, 500);

/// Writes the plot as `STEM.png` (rasterised, text with the DejaVu Sans font) and `STEM.svg`.
fn plot(stem: &Path, title: &str, y_label: &str, series: &[Series]) -> Result<()> {
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
    series: &[Series],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let n = series
        .iter()
        .flat_map(|s| s.1.iter().map(|p| p.0 + 1.0))
        .fold(1.0f64, f64::max);
    let ymax = series
        .iter()
        .flat_map(|s| s.1.iter().map(|p| p.1))
        .fold(0.0f64, f64::max)
        * 1.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(0f64..n, 0f64..ymax.max(1.0))?;
    chart
        .configure_mesh()
        .x_desc("frame")
        .y_desc(y_label)
        .draw()?;
    let palette = [RED, BLUE, GREEN, MAGENTA, CYAN, BLACK];
    for (k, (name, ys)) in series.iter().enumerate() {
        let c = palette[k % palette.len()];
        chart
            .draw_series(LineSeries::new(ys.iter().copied(), c.stroke_width(2)))?
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
        if !xtask::vulkan::is_root() {
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

/// Replaces (or appends) the section between `begin` and `end` of the file `path`.
pub fn splice_into_doc(path: &Path, begin: &str, end: &str, section: &str) -> Result<()> {
    let old = std::fs::read_to_string(path).unwrap_or_else(|_| {
        "# Figures\n\nReproductions of the papers' figures and tables, generated by `cargo xtask figures`.\n"
            .to_string()
    });
    let new = crate::figures_table::splice(&old, begin, end, section);
    std::fs::write(path, new).with_context(|| format!("writing {}", path.display()))
}

fn number(x: f64) -> String {
    format!("{x}")
}

/// The error rows of one run's measured frames.
fn push_errors(t: &mut Table, config: &str, frames: &[Frame]) {
    for f in frames {
        if let Some(e) = f.error {
            t.push(vec![
                f.frame.to_string(),
                config.to_string(),
                number(e[0]),
                number(e[1]),
                number(e[2]),
            ]);
        }
    }
}

/// Runs the experiment with the release `subdiv` binary `exe` and writes the figures; refuses
/// above a 1-minute load of [`MAX_LOAD`] unless `force`.
pub fn run(root: &Path, exe: &Path, force: bool) -> Result<()> {
    let t0 = Instant::now();
    let load_start = load_average();
    if load_start > MAX_LOAD && !force {
        bail!(
            "the 1-minute load average is {load_start:.2}, above {MAX_LOAD}: frame rates measured \
             now would show the other work, not subdiv. Run again on an idle machine, or pass \
             --force (the figures then say they were forced)"
        );
    }
    let dir: PathBuf = root.join("docs/figures");
    std::fs::create_dir_all(&dir)?;
    let (n5, n7) = (FRAMES_TESSELLATION.to_string(), FRAMES_RENDERED.to_string());
    let every = ERROR_EVERY.to_string();
    let esize = format!("{}x{}", ERROR_SIZE.0, ERROR_SIZE.1);
    let errors = [
        "--error-every",
        &every,
        "--error-size",
        &esize,
        "--reference-depth",
        REFERENCE_DEPTH,
    ];
    let measured = |extra: &[&str]| -> Result<Vec<Frame>> {
        let mut a = vec!["--no-render", "--frames", &n5];
        a.extend(errors);
        a.extend(extra);
        bench(exe, &a)
    };
    // Figs. 5 and 6: tessellation along one orbit, with the image error of every 10th frame.
    let adaptive = measured(&[])?;
    let uniform: Vec<Vec<Frame>> = UNIFORM
        .iter()
        .map(|d| measured(&["--depth", &d.to_string()]))
        .collect::<Result<_>>()?;
    // Fig. 7: rendered frame rates (lavapipe).
    let fixed: Vec<Vec<Frame>> = UNIFORM
        .iter()
        .map(|d| bench(exe, &["--frames", &n7, "--depth", &d.to_string()]))
        .collect::<Result<_>>()?;
    let free = bench(exe, &["--frames", &n7])?;
    let fps_of = |v: &[Frame]| median(&v.iter().skip(1).map(|f| f.fps).collect::<Vec<_>>());
    // The paper's scenario under both controllers, image error measured (untimed).
    let (t1, t2) = (
        format!("{:.2}", PAPER_TARGETS.0),
        format!("{:.2}", PAPER_TARGETS.1),
    );
    let scenario = |control: &str| -> Result<Vec<Frame>> {
        let mut a = vec!["--frames", &n7, "--target-fps", &t1, "--switch-fps", &t2];
        a.extend(["--control", control]);
        a.extend(errors);
        bench(exe, &a)
    };
    let budget = scenario("budget")?;
    let paper = scenario("paper")?;
    // A level of quality for free: held at uniform depth 2's and 3's rates.
    let at = [fps_of(&fixed[0]), fps_of(&fixed[1])];
    let held: Vec<Vec<Frame>> = at
        .iter()
        .map(|f| {
            let t = format!("{f:.2}");
            let mut a = vec!["--frames", &n7, "--target-fps", &t, "--control", "budget"];
            a.extend(errors);
            bench(exe, &a)
        })
        .collect::<Result<_>>()?;
    let runs = Runs {
        adaptive,
        uniform,
        fixed,
        free,
        budget,
        paper,
        held,
        held_targets: at,
    };
    let data = tables(&runs, t0, (load_start, load_average()), force)?;
    data.write(&dir)?;
    plots(&dir, &data)?;
    let md = crate::figures_cc_text::markdown(&data)?;
    splice_into_doc(
        &root.join("docs/figures.md"),
        crate::figures_cc_text::BEGIN,
        crate::figures_cc_text::END,
        &md,
    )?;
    println!(
        "figures: wrote docs/figures/{{fig5_triangles,fig5_error,fig6_quads,fig7_framerate}} (.png, .svg), their CSV \
         files and docs/figures.md in {:.0} s",
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Every run of the Catmull-Clark figures.
struct Runs {
    /// Figs. 5 and 6, not rendered: adaptive without control, uniform depths 2, 3, 4.
    adaptive: Vec<Frame>,
    uniform: Vec<Vec<Frame>>,
    /// Fig. 7, rendered: uniform depths 2, 3, 4, adaptive without control.
    fixed: Vec<Vec<Frame>>,
    free: Vec<Frame>,
    /// The paper's scenario under the predictive and the paper's controller.
    budget: Vec<Frame>,
    paper: Vec<Frame>,
    /// The predictive controller held at uniform depth 2's and 3's rates.
    held: Vec<Vec<Frame>>,
    held_targets: [f64; 2],
}

/// The runs as the tables of [`CcData`].
fn tables(
    r: &Runs,
    t0: Instant,
    (load_start, load_end): (f64, f64),
    force: bool,
) -> Result<CcData> {
    let faces = subdiv::helmet40()?.num_faces();
    let (w, h) = SIZE.split_once('x').context("SIZE is WxH")?;
    let mut run = Table::new(&["key", "value"]);
    for (k, v) in [
        ("faces", faces.to_string()),
        ("width", w.into()),
        ("height", h.into()),
        ("samples", SAMPLES.into()),
        ("orbit_step_deg", ORBIT_STEP_DEG.into()),
        ("max_depth", MAX_DEPTH.into()),
        ("error_every", ERROR_EVERY.to_string()),
        ("error_width", ERROR_SIZE.0.to_string()),
        ("error_height", ERROR_SIZE.1.to_string()),
        ("reference_depth", REFERENCE_DEPTH.into()),
        ("switch_frame", (r.budget.len() / 2).to_string()),
        ("held2_target", format!("{:.2}", r.held_targets[0])),
        ("held3_target", format!("{:.2}", r.held_targets[1])),
        ("seconds", format!("{:.0}", t0.elapsed().as_secs_f64())),
        ("load_start", format!("{load_start:.2}")),
        ("load_end", format!("{load_end:.2}")),
        ("max_load", format!("{MAX_LOAD}")),
        (
            "forced",
            u8::from(force && load_start > MAX_LOAD).to_string(),
        ),
    ] {
        run.push(vec![k.to_string(), v]);
    }
    let mut triangles = Table::new(&["frame", "adaptive", "uniform2", "uniform3", "uniform4"]);
    for (i, f) in r.adaptive.iter().enumerate() {
        let mut row = vec![i.to_string(), f.triangles.to_string()];
        row.extend(r.uniform.iter().map(|u| u[i].triangles.to_string()));
        triangles.push(row);
    }
    let depths = r.adaptive.iter().map(|f| f.quads.len()).max().unwrap_or(0);
    let hdr: Vec<String> = (0..depths).map(|d| format!("depth{d}")).collect();
    let mut h: Vec<&str> = vec!["frame"];
    h.extend(hdr.iter().map(String::as_str));
    let mut quads = Table::new(&h);
    for (i, f) in r.adaptive.iter().enumerate() {
        let mut row = vec![i.to_string()];
        row.extend((0..depths).map(|d| f.quads.get(d).copied().unwrap_or(0).to_string()));
        quads.push(row);
    }
    let mut framerate = Table::new(&crate::figures_cc_text::FRAMERATE_COLUMNS);
    let switch = r.budget.len() / 2;
    for i in 0..r.budget.len() {
        let (b, p) = (&r.budget[i], &r.paper[i]);
        let mut row = vec![i.to_string()];
        row.extend(r.fixed.iter().map(|u| number(u[i].fps)));
        row.push(number(r.free[i].fps));
        row.push(number(b.fps));
        row.push(number(p.fps));
        let t = if i < switch {
            PAPER_TARGETS.0
        } else {
            PAPER_TARGETS.1
        };
        row.push(number(t));
        row.push(number(b.predicted_ms));
        row.push(b.triangles.to_string());
        row.push(p.triangles.to_string());
        row.push(p.maxsd.to_string());
        row.push(number(p.share));
        row.extend(r.held.iter().map(|v| number(v[i].fps)));
        row.extend(r.held.iter().map(|v| v[i].triangles.to_string()));
        framerate.push(row);
    }
    let mut error = Table::new(&[
        "frame",
        "config",
        "silhouette_px_max",
        "silhouette_px_p99",
        "shading_deg_p99",
    ]);
    push_errors(&mut error, "adaptive", &r.adaptive);
    for (d, u) in UNIFORM.iter().zip(&r.uniform) {
        push_errors(&mut error, &format!("uniform{d}"), u);
    }
    push_errors(&mut error, "budget", &r.budget);
    push_errors(&mut error, "paper", &r.paper);
    push_errors(&mut error, "held2", &r.held[0]);
    push_errors(&mut error, "held3", &r.held[1]);
    Ok(CcData {
        run,
        triangles,
        quads,
        framerate,
        error,
    })
}

/// The plots of the figures, from their tables.
pub fn plots(dir: &Path, d: &CcData) -> Result<()> {
    register_font()?;
    let col = |t: &Table, c: &str| t.f64s(c);
    let mut s5 = vec![per_frame(
        "adaptive (depths 0-4)",
        &col(&d.triangles, "adaptive")?,
    )];
    for k in UNIFORM {
        let name = format!("uniform{k}");
        s5.push(per_frame(
            &format!("uniform depth {k}"),
            &col(&d.triangles, &name)?,
        ));
    }
    plot(
        &dir.join("fig5_triangles"),
        "Fig. 5: triangles per frame (40 helmets, orbit)",
        "triangles",
        &s5,
    )?;
    let mut e5 = Vec::new();
    for (name, label) in [
        ("adaptive", "adaptive".to_string()),
        ("uniform2", "uniform depth 2".into()),
        ("uniform3", "uniform depth 3".into()),
        ("uniform4", "uniform depth 4".into()),
    ] {
        let t = d.error.filter("config", name)?;
        let pts = col(&t, "frame")?
            .into_iter()
            .zip(col(&t, "shading_deg_p99")?)
            .collect();
        e5.push((label, pts));
    }
    plot(
        &dir.join("fig5_error"),
        "Fig. 5: shading error per frame (99th percentile of the normal angle)",
        "shading error (degrees)",
        &e5,
    )?;
    let s6: Vec<Series> = d
        .quads
        .header
        .iter()
        .filter(|h| h.starts_with("depth"))
        .map(|h| Ok(per_frame(&h.replace("depth", "depth "), &col(&d.quads, h)?)))
        .collect::<Result<_>>()?;
    plot(
        &dir.join("fig6_quads"),
        "Fig. 6: quads per depth per frame (adaptive)",
        "quads",
        &s6,
    )?;
    let mut s7 = Vec::new();
    for (c, label) in [
        ("uniform2", "uniform depth 2"),
        ("uniform3", "uniform depth 3"),
        ("uniform4", "uniform depth 4"),
        ("adaptive", "adaptive, no control"),
        ("budget", "adaptive, predictive control"),
        ("paper", "adaptive, the paper's control"),
        ("target", "target"),
    ] {
        s7.push(per_frame(label, &col(&d.framerate, c)?));
    }
    plot(
        &dir.join("fig7_framerate"),
        "Fig. 7: frames per second (lavapipe)",
        "fps",
        &s7,
    )
}
