//! `subdiv`: the command-line front end. It parses arguments and wires the library crates
//! together; all geometry lives in the libraries.

#[macro_use]
mod out;

mod adaptive_args;
mod bench;
mod bench_animate;
mod bench_evaluate;
mod bench_framerate;
mod bench_quality;
mod camera_args;
mod choices;
mod dicing_args;
mod doi_args;
mod evaluate;
mod info;
mod limit_args;
mod load;
mod logger;
mod progress;
mod refine;
mod render;
mod surface_args;
mod tessellate;
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// mimalloc: the exact evaluator and the adaptive frames allocate many small buffers, which
/// glibc's allocator serves several times slower (docs/performance.md).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Adaptive, crack-free tessellation of subdivision surfaces.
#[derive(Parser, Debug)]
#[command(name = "subdiv", version, about)]
struct Cli {
    /// Refuse cages with tag lines that are not applied (unknown tags, hierarchical edits, ...)
    /// instead of warning about them.
    #[arg(long, global = true)]
    strict: bool,
    /// More messages on stderr: `-v` debug lines, `-vv` trace lines.
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    verbose: u8,
    /// Errors only on stderr: no warnings, notes or progress bars.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Counts, face sizes, valences, boundaries, creases and genus of a cage, and whether (and
    /// why) it would be refused.
    Info(info::InfoArgs),
    /// Tessellate the limit surface and write it as OBJ, glTF or PLY (limit points and limit
    /// normals; the format by the extension of -o).
    Tessellate(tessellate::TessellateArgs),
    /// Adaptive Loop subdivision driven by a Degree-of-Interest function (Isenberg et al. 2003).
    Refine(refine::RefineArgs),
    /// The exact limit surface at given (face, u, v) points: position and derivatives, one
    /// line a point.
    Evaluate(evaluate::EvaluateArgs),
    /// Benchmarks (median of repeated runs).
    Bench(bench::BenchArgs),
    /// Render the limit surface headless with Vulkan to PNG (and EXR).
    Render(render::RenderArgs),
    /// Open the interactive Vulkan viewer on the limit surface.
    #[command(after_help = subdiv::vk::viewer::KEY_HELP)]
    View(view::ViewArgs),
}

fn main() -> ExitCode {
    // A CPU Vulkan driver (lavapipe) draws from the C heap: keep it between frames.
    subdiv::vk::keep_freed_heap();
    let cli = Cli::parse();
    logger::init(cli.verbose, cli.quiet);
    progress::init(cli.quiet);
    load::set_strict(cli.strict);
    let result = match cli.command {
        Command::Info(a) => info::run(&a),
        Command::Tessellate(a) => tessellate::run(&a),
        Command::Refine(a) => refine::run(&a),
        Command::Evaluate(a) => evaluate::run(&a),
        Command::Bench(a) => bench::run(&a),
        Command::Render(a) => render::run(&a),
        Command::View(a) => view::run(&a),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            // The whole chain on one line, each cause once: `error: FILE: cause: cause`.
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
