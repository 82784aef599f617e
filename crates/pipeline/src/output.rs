//! The output folder: who owns it, and writing it so that it never looks complete unless it
//! is.
//!
//! Rules: a path that is a file is refused; a folder written by another pipeline (its marker
//! names another pipeline) or a non-empty folder flatcut did not write is refused unless
//! forced; an output file never replaces an input, and no input is removed as a file of an
//! earlier run. Every file is written atomically (a
//! temporary file beside it, then a rename); the previous report.json is removed first and the
//! new one written last, so a folder with a report.json is a finished run. Files a previous
//! run of the same pipeline wrote and this one does not are removed.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::PipelineError;

/// The marker file naming the pipeline that owns the folder.
pub const MARKER: &str = ".flatcut-pipeline";
/// The report, written last.
pub const REPORT: &str = "report.json";
/// Wall times, written just before the report.
pub const TIMINGS: &str = "timings.json";

/// Checks that `dir` may receive the results of pipeline `name` (see the module rules).
/// `inputs` are the files the run reads; `outputs` the names it will write inside `dir`.
/// Creates nothing.
pub fn check(
    dir: &Path,
    name: &str,
    force: bool,
    inputs: &[PathBuf],
    outputs: &[String],
) -> Result<(), PipelineError> {
    if dir.exists() && !dir.is_dir() {
        return Err(PipelineError::OutputIsFile {
            path: dir.to_path_buf(),
        });
    }
    // A parent component that is a file fails later with a plain I/O error; say it now.
    for anc in dir.ancestors().skip(1) {
        if anc.as_os_str().is_empty() {
            break;
        }
        if anc.exists() && !anc.is_dir() {
            return Err(PipelineError::OutputIsFile {
                path: anc.to_path_buf(),
            });
        }
    }
    if dir.is_dir() && !force {
        let owner = std::fs::read_to_string(dir.join(MARKER))
            .ok()
            .map(|s| s.trim().to_string());
        match owner {
            Some(o) if o == name => {}
            Some(o) => {
                return Err(PipelineError::OutputForeign {
                    path: dir.to_path_buf(),
                    owner: Some(o),
                });
            }
            None => {
                let empty = std::fs::read_dir(dir)
                    .map_err(|source| PipelineError::Write {
                        path: dir.to_path_buf(),
                        source,
                    })?
                    .next()
                    .is_none();
                if !empty {
                    return Err(PipelineError::OutputForeign {
                        path: dir.to_path_buf(),
                        owner: None,
                    });
                }
            }
        }
    }
    if dir.is_dir() {
        let inputs: Vec<PathBuf> = inputs
            .iter()
            .filter_map(|p| std::fs::canonicalize(p).ok())
            .collect();
        for name in outputs
            .iter()
            .map(String::as_str)
            .chain([MARKER, REPORT, TIMINGS])
        {
            let path = dir.join(name);
            if let Ok(c) = std::fs::canonicalize(&path)
                && inputs.contains(&c)
            {
                return Err(PipelineError::WouldOverwriteInput { path });
            }
        }
        // Files an earlier run wrote and this one does not are removed by `write`: never an
        // input (a run reading an earlier run's piece from the folder deleted it).
        for stale in stale_files(dir, |f| outputs.iter().any(|o| o == f)) {
            let path = dir.join(&stale);
            if let Ok(c) = std::fs::canonicalize(&path)
                && inputs.contains(&c)
            {
                return Err(PipelineError::WouldRemoveInput { path });
            }
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), PipelineError> {
    let err = |source| PipelineError::Write {
        path: path.to_path_buf(),
        source,
    };
    let dir = path.parent().unwrap_or(Path::new("."));
    let file = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{file}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(err(e));
    }
    Ok(())
}

/// The file names listed in an existing report.json (`files[].name`), to remove the ones
/// this run no longer writes.
fn previous_files(dir: &Path) -> Vec<String> {
    let Ok(text) = std::fs::read_to_string(dir.join(REPORT)) else {
        return Vec::new();
    };
    let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Vec::new();
    };
    v.get("files")
        .and_then(|f| f.as_array())
        .map(|a| {
            a.iter()
                .filter_map(|f| f.get("name")?.as_str().map(str::to_string))
                .collect()
        })
        .unwrap_or_default()
}

/// The files an earlier run wrote in `dir` (its report.json's list, names that stay inside
/// the folder) that this run, which writes the names `written` accepts, does not: the ones
/// [`write`] removes, and which [`check`] makes sure are no input.
fn stale_files(dir: &Path, written: impl Fn(&str) -> bool) -> Vec<String> {
    previous_files(dir)
        .into_iter()
        .filter(|f| is_plain_relative(f) && !written(f))
        .collect()
}

/// A name from a report is only trusted if it stays inside the folder.
fn is_plain_relative(name: &str) -> bool {
    let p = Path::new(name);
    !name.is_empty()
        && p.components()
            .all(|c| matches!(c, std::path::Component::Normal(_)))
}

/// Writes the run into `dir` (after [`check`]): marker, files, timings, then the report.
pub fn write(
    dir: &Path,
    name: &str,
    files: &BTreeMap<String, Vec<u8>>,
    timings: &[u8],
    report: &[u8],
) -> Result<(), PipelineError> {
    let mkdir = |d: &Path| {
        std::fs::create_dir_all(d).map_err(|source| PipelineError::Write {
            path: d.to_path_buf(),
            source,
        })
    };
    mkdir(dir)?;
    let stale = stale_files(dir, |f| files.contains_key(f));
    let report_path = dir.join(REPORT);
    if report_path.exists() {
        std::fs::remove_file(&report_path).map_err(|source| PipelineError::Write {
            path: report_path.clone(),
            source,
        })?;
    }
    write_atomic(&dir.join(MARKER), format!("{name}\n").as_bytes())?;
    for old in stale {
        let _ = std::fs::remove_file(dir.join(&old));
    }
    for (rel, bytes) in files {
        let path = dir.join(rel);
        if let Some(parent) = path.parent() {
            mkdir(parent)?;
        }
        write_atomic(&path, bytes)?;
    }
    write_atomic(&dir.join(TIMINGS), timings)?;
    write_atomic(&report_path, report)
}
