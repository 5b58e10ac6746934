//! `shadeballs export-shader`: the ball shading for another engine (docs/interop.md, "The
//! BRDF in another engine"): `wgsl::export::ball_program` (the crate's library WGSL and a
//! fragment entry point `fs_ball` that shades one ball), validated by naga and written by
//! its WGSL, GLSL, HLSL or MSL back end.

use std::path::PathBuf;

/// The languages naga writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Lang {
    /// WGSL, as the crate's renderer composes it (one flat file).
    Wgsl,
    /// GLSL 4.50 (desktop), a fragment shader (`.frag`).
    Glsl,
    /// HLSL, shader model 5.1.
    Hlsl,
    /// Metal Shading Language 1.0 (naga's default).
    Msl,
}

/// Flags of `shadeballs export-shader`.
#[derive(clap::Args)]
pub(crate) struct ExportShaderArgs {
    /// The language to write.
    #[arg(long)]
    pub lang: Lang,
    /// The file to write (any name; a GLSL validator reads `.frag` as a fragment shader).
    #[arg(long)]
    pub out: PathBuf,
}

/// The entry point the exported program has.
pub(crate) const ENTRY_POINT: &str = "fs_ball";

pub(crate) fn run(args: ExportShaderArgs) -> anyhow::Result<()> {
    crate::output::check_output_path(&args.out)?;
    // Issue 38: the file's folder takes a new file before the program is translated.
    super::guard::check_out(&args.out, &[])?;
    let text = translate(args.lang).map_err(|message| crate::Error::Invalid {
        what: "exported shader",
        message,
    })?;
    crate::output::write_atomic(&args.out, text.as_bytes())?;
    eprintln!(
        "wrote the ball shading as {:?} (entry point {ENTRY_POINT}, {} bytes) -> {}",
        args.lang,
        text.len(),
        args.out.display()
    );
    Ok(())
}

/// The program in `lang`, or naga's reason on one line.
pub(crate) fn translate(lang: Lang) -> Result<String, String> {
    use naga::back;
    let source = crate::wgsl::export::ball_program();
    let module = naga::front::wgsl::parse_str(&source).map_err(|e| e.emit_to_string(&source))?;
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .map_err(|e| format!("{e:?}"))?;
    let text = match lang {
        Lang::Wgsl => back::wgsl::write_string(&module, &info, back::wgsl::WriterFlags::empty())
            .map_err(|e| e.to_string())?,
        Lang::Glsl => {
            let mut out = String::new();
            let options = back::glsl::Options {
                version: back::glsl::Version::Desktop(450),
                ..Default::default()
            };
            let pipeline = back::glsl::PipelineOptions {
                shader_stage: naga::ShaderStage::Fragment,
                entry_point: ENTRY_POINT.to_string(),
                multiview: None,
            };
            back::glsl::Writer::new(
                &mut out,
                &module,
                &info,
                &options,
                &pipeline,
                naga::proc::BoundsCheckPolicies::default(),
            )
            .map_err(|e| e.to_string())?
            .write()
            .map_err(|e| e.to_string())?;
            out
        }
        Lang::Hlsl => {
            let mut out = String::new();
            let options = back::hlsl::Options::default();
            let pipeline = back::hlsl::PipelineOptions {
                entry_point: Some((naga::ShaderStage::Fragment, ENTRY_POINT.to_string())),
            };
            back::hlsl::Writer::new(&mut out, &options, &pipeline)
                .write(&module, &info, None)
                .map_err(|e| e.to_string())?;
            out
        }
        Lang::Msl => {
            back::msl::write_string(
                &module,
                &info,
                &back::msl::Options::default(),
                &back::msl::PipelineOptions::default(),
            )
            .map_err(|e| e.to_string())?
            .0
        }
    };
    // Every language takes a `//` comment.
    Ok(format!(
        "// shadeballs {}: the ball shading of the Kulla-Conty BRDF (docs/interop.md), \
         entry point {ENTRY_POINT}; written by naga from the crate's WGSL.\n{text}",
        env!("CARGO_PKG_VERSION"),
    ))
}
