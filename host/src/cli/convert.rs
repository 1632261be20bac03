//! `spectrace convert scene.xml -o scene.ron`: a Mitsuba 3 XML scene written as the spectrace
//! RON scene it becomes, with the list of what the conversion changed or dropped.

use crate::scene::mitsuba;
use clap::Args;
use ron::Value;
use std::path::{Path, PathBuf};

/// Arguments of `convert`.
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The Mitsuba 3 scene (.xml).
    pub scene: PathBuf,
    /// The RON scene to write (default: the scene's name with .ron, beside it).
    #[arg(short = 'o', long = "output")]
    pub output: Option<PathBuf>,
    /// Set a scene parameter, as Mitsuba's `-D name=value` (wins over the file's `default`).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
}

/// Run `convert`.
pub fn run(args: &ConvertArgs) -> Result<(), String> {
    let defines = mitsuba::parse_defines(&args.define)?;
    let conv = mitsuba::convert_file(&args.scene, &defines).map_err(|e| e.to_string())?;
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| args.scene.with_extension("ron"));
    let mut desc = conv.desc;
    let src_dir = args.scene.parent().unwrap_or(Path::new("."));
    let out_dir = out.parent().unwrap_or(Path::new("."));
    let same_dir = match (
        std::fs::canonicalize(nonempty(src_dir)),
        std::fs::canonicalize(nonempty(out_dir)),
    ) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if !same_dir {
        // Files the scene names are relative to the XML's directory: made absolute so the RON
        // file finds them wherever it is written.
        let base = std::fs::canonicalize(nonempty(src_dir))
            .map_err(|e| format!("{}: {e}", src_dir.display()))?;
        for m in &mut desc.materials {
            absolutise(&mut m.params, &base);
        }
        for o in &mut desc.objects {
            absolutise(&mut o.params, &base);
        }
        for l in &mut desc.lights {
            absolutise(&mut l.params, &base);
        }
    }
    let pretty = ron::ser::PrettyConfig::new()
        .depth_limit(4)
        .indentor("    ".into());
    let body = ron::ser::to_string_pretty(&desc, pretty).map_err(|e| e.to_string())?;
    let mut text = format!(
        "// Converted from {} by `spectrace convert`.\n",
        args.scene.display()
    );
    if conv.notes.is_empty() {
        text.push_str("// Everything in the Mitsuba scene was converted as it is.\n");
    } else {
        text.push_str("// What the conversion changed or dropped:\n");
        for n in &conv.notes {
            text.push_str(&format!("// - {n}\n"));
        }
    }
    text.push_str(&body);
    text.push('\n');
    std::fs::write(&out, text).map_err(|e| format!("{}: {e}", out.display()))?;
    println!(
        "{} → {}: {} materials, {} objects, {} lights, {} cameras",
        args.scene.display(),
        out.display(),
        desc.materials.len(),
        desc.objects.len(),
        desc.lights.len(),
        desc.cameras.len()
    );
    if conv.notes.is_empty() {
        println!("nothing changed or dropped");
    } else {
        println!("changed or dropped:");
        for n in &conv.notes {
            println!("  - {n}");
        }
    }
    Ok(())
}

fn nonempty(p: &Path) -> &Path {
    if p.as_os_str().is_empty() {
        Path::new(".")
    } else {
        p
    }
}

/// Every relative `file` (or `texture: "…"`) value in `v` made absolute against `base`.
fn absolutise(v: &mut Value, base: &Path) {
    match v {
        Value::Map(m) => {
            let mut out = ron::Map::new();
            for (k, x) in m.iter() {
                let mut x = x.clone();
                let key_is = |name: &str| matches!(k, Value::String(s) if s == name);
                match &mut x {
                    Value::String(s)
                        if (key_is("file") || key_is("texture"))
                            && Path::new(s.as_str()).is_relative() =>
                    {
                        *s = base.join(s.as_str()).to_string_lossy().into_owned();
                    }
                    other => absolutise(other, base),
                }
                out.insert(k.clone(), x);
            }
            *m = out;
        }
        Value::Seq(items) => items.iter_mut().for_each(|i| absolutise(i, base)),
        _ => {}
    }
}
