//! Helpers shared by the commands: unit parsing, the input-overwrite guard and atomic text
//! output.

use std::path::Path;

use anyhow::Context;
use flatcut_io::Units;

/// The units a file is read in: `--units` when given, else metres for glTF/GLB (the glTF
/// specification fixes metres) and millimetres for every other format.
pub fn units_for(path: &Path, given: Option<Units>) -> Units {
    given.unwrap_or(flatcut_io::Format::from_extension(path).map_or(Units::Mm, Units::default_for))
}

/// Parses `--units` for clap, listing the accepted values on error.
pub fn parse_units(s: &str) -> Result<Units, String> {
    s.parse::<Units>().map_err(|e| e.to_string())
}

/// Inputs are never overwritten, and no output overwrites another: refuses an output path
/// that names one of `inputs` or another of `outputs` (each given with the argument that names
/// it, for the message). Two paths name one file when they are the same file on disk (also
/// through a hard or symbolic link: `same-file` compares device and inode), or, for a file
/// not written yet, the same name in the same directory however spelt (`out.obj`,
/// `./out.obj`).
pub fn refuse_overwrite(inputs: &[(&str, &Path)], outputs: &[(&str, &Path)]) -> anyhow::Result<()> {
    for (k, &(what, out)) in outputs.iter().enumerate() {
        if let Some((named, input)) = inputs.iter().find(|(_, i)| same_path(i, out)) {
            anyhow::bail!(
                "{what} {} is the input {named} ({}); flatcut never overwrites its input: choose another path",
                out.display(),
                input.display()
            );
        }
        if let Some((other, _)) = outputs[..k].iter().find(|(_, o)| same_path(o, out)) {
            anyhow::bail!(
                "{what} and {other} are both {}: one would overwrite the other; choose two paths",
                out.display()
            );
        }
    }
    Ok(())
}

fn same_path(a: &Path, b: &Path) -> bool {
    if let Ok(same) = same_file::is_same_file(a, b) {
        return same;
    }
    // At least one does not exist yet: compare the directory (resolved) and the name.
    let spelt = |p: &Path| {
        let dir = p
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        (
            std::fs::canonicalize(dir).ok(),
            p.file_name().map(ToOwned::to_owned),
        )
    };
    match (spelt(a), spelt(b)) {
        ((Some(da), Some(na)), (Some(db), Some(nb))) => da == db && na == nb,
        _ => a == b,
    }
}

/// Writes `text` to `path` atomically (a temporary file beside it, then a rename), so a
/// reader never sees half a report.
pub fn write_text_atomic(path: &Path, text: &str) -> anyhow::Result<()> {
    write_bytes_atomic(path, text.as_bytes())
}

/// Writes bytes atomically: a temporary file beside `path`, then a rename, so that no reader
/// (and no crash) ever leaves a half-written file under the final name.
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file path", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    std::fs::write(&tmp, bytes).with_context(|| format!("cannot write {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| {
        let _ = std::fs::remove_file(&tmp);
        format!(
            "cannot move {} into place as {}",
            tmp.display(),
            path.display()
        )
    })
}

/// Prints `text` to standard output. A closed pipe (`flatcut info x | head`) is not an error:
/// the reader has what it wanted.
pub fn emit(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(e).context("cannot write to standard output")
        }
        _ => Ok(()),
    }
}
