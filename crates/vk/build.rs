//! Compiles the GLSL shaders in `src/shaders/` to SPIR-V with naga.
//!
//! Output goes to `$OUT_DIR/<name>.spv` and is embedded by `src/shaders/mod.rs`.
//! Writer flags are fixed (no debug info, no Y flip) so debug and release
//! builds embed byte-identical SPIR-V, which keeps golden images identical.

use std::path::{Path, PathBuf};

use naga::back::spv;
use naga::front::glsl;
use naga::valid::{Capabilities, ValidationFlags, Validator};

/// (output name, source file, stage, extra `#define`s)
const SHADERS: &[(&str, &str, naga::ShaderStage, &[&str])] = &[
    ("mesh.vert", "mesh.vert", naga::ShaderStage::Vertex, &[]),
    ("mesh.frag", "mesh.frag", naga::ShaderStage::Fragment, &[]),
    (
        "mesh_color.frag",
        "mesh.frag",
        naga::ShaderStage::Fragment,
        &["COLOR_ONLY"],
    ),
    ("line.vert", "line.vert", naga::ShaderStage::Vertex, &[]),
    ("line.frag", "line.frag", naga::ShaderStage::Fragment, &[]),
    (
        "overlay.vert",
        "overlay.vert",
        naga::ShaderStage::Vertex,
        &[],
    ),
    (
        "overlay.frag",
        "overlay.frag",
        naga::ShaderStage::Fragment,
        &[],
    ),
];

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default());
    let shader_dir = manifest.join("src").join("shaders");
    println!("cargo:rerun-if-changed={}", shader_dir.display());
    for (name, file, stage, defines) in SHADERS {
        let path = shader_dir.join(file);
        println!("cargo:rerun-if-changed={}", path.display());
        if let Err(message) = compile(&path, *stage, defines, &out_dir.join(format!("{name}.spv")))
        {
            // A build script reports failure by exiting non-zero with a message.
            eprintln!("error: shader {}: {message}", path.display());
            std::process::exit(1);
        }
    }
}

fn compile(
    path: &Path,
    stage: naga::ShaderStage,
    defines: &[&str],
    out: &Path,
) -> Result<(), String> {
    let source = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let mut options = glsl::Options::from(stage);
    for define in defines {
        options
            .defines
            .insert((*define).to_string(), "1".to_string());
    }
    let module = glsl::Frontend::default()
        .parse(&options, &source)
        .map_err(|e| e.emit_to_string(&source))?;
    let info = Validator::new(ValidationFlags::all(), Capabilities::IMMEDIATES)
        .validate(&module)
        .map_err(|e| e.emit_to_string(&source))?;
    let spv_options = spv::Options {
        lang_version: (1, 0),
        // Deliberately without ADJUST_COORDINATE_SPACE (it flips Y) and DEBUG.
        flags: spv::WriterFlags::LABEL_VARYINGS | spv::WriterFlags::CLAMP_FRAG_DEPTH,
        ..spv::Options::default()
    };
    let pipeline = spv::PipelineOptions {
        shader_stage: stage,
        entry_point: "main".to_string(),
    };
    let words =
        spv::write_vec(&module, &info, &spv_options, Some(&pipeline)).map_err(|e| e.to_string())?;
    let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
    std::fs::write(out, bytes).map_err(|e| e.to_string())
}
