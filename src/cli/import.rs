//! `shadeballs import`: a glTF 2.0 file (`.gltf`, `.glb`) written as a scene file that
//! `render` and `view` open (docs/interop.md, "glTF in"). `render --scene FILE.gltf` and
//! `view --scene FILE.gltf` read the same scene directly ([`super::SceneArgs::load`]).

use std::path::PathBuf;

use crate::import::{self, Imported};

/// Flags of `shadeballs import`.
#[derive(clap::Args)]
pub(crate) struct ImportArgs {
    /// The glTF file: .gltf (its buffers beside it) or .glb.
    pub file: PathBuf,
    /// The scene file to write (.toml): one ball per sphere the file places (else one per
    /// material, in a chart), each labelled with its material's name (`label`; a chart's labels on).
    #[arg(long)]
    pub out: PathBuf,
}

/// The render size the scene file's header suggests.
const SIZE: (u32, u32) = (1280, 720);

pub(crate) fn run(args: ImportArgs) -> anyhow::Result<()> {
    if crate::output::extension(&args.out) != "toml" {
        return Err(crate::Error::Format {
            path: args.out,
            expected: "expected a .toml scene file",
        }
        .into());
    }
    crate::output::check_output_path(&args.out)?;
    // Issue 38: the scene file replaces neither the glTF file nor a file it names, and its
    // folder takes a new file, before the glTF is read.
    let mut inputs = vec![("the glTF file".to_string(), args.file.clone())];
    inputs.extend(super::guard::gltf_files(&args.file));
    super::guard::check_out(&args.out, &inputs)?;
    let imported = import::load(&args.file)?;
    super::print_import_notices(&imported);
    let text = scene_text(&imported, &args.file).map_err(|message| crate::Error::Scene {
        path: args.file.clone(),
        message,
    })?;
    crate::output::write_atomic(&args.out, text.as_bytes())?;
    eprintln!(
        "imported {} ball(s) from {} material(s) ({}; {}) -> {}",
        imported.scene.balls.len(),
        imported.materials.len(),
        if imported.placed {
            "where the file places its spheres"
        } else {
            "a chart: the file places no sphere"
        },
        if imported.camera_from_file {
            "the file's camera"
        } else {
            "a camera framing them"
        },
        args.out.display()
    );
    Ok(())
}

/// The scene file of `imported`: the viewer's exact writer (every value loads back to the
/// same double), a header naming the source, and before each ball a comment naming its
/// material and node.
pub(crate) fn scene_text(imported: &Imported, source: &std::path::Path) -> Result<String, String> {
    let text = crate::viewer::save::scene_toml(&imported.scene, SIZE)?;
    let (_, body) = text.split_once('\n').unwrap_or(("", &text));
    let mut out = format!(
        "# Imported by `shadeballs import` from '{}': {}.\n# `shadeballs render --scene <this \
         file>` draws it.\n",
        source.display(),
        if imported.placed {
            "one ball per sphere, where the file places it"
        } else {
            "one ball per material, in a chart"
        }
    );
    let mut balls = imported.ball_materials.iter().zip(&imported.ball_nodes);
    for (i, part) in body.split("\n[[ball]]\n").enumerate() {
        if i > 0 {
            let (&k, node) = balls.next().ok_or("more balls written than imported")?;
            let m = &imported.materials[k];
            let index = m.index.map_or("the default material".to_string(), |i| {
                format!("glTF material {i}")
            });
            let node = node
                .as_ref()
                .map_or(String::new(), |n| format!(", node '{n}'"));
            out.push_str(&format!(
                "\n# Material '{}' ({index}{node})\n[[ball]]\n",
                m.name.replace('\n', " ")
            ));
        }
        out.push_str(part);
        if i == 0 && !part.ends_with('\n') {
            out.push('\n');
        }
    }
    Ok(out)
}
