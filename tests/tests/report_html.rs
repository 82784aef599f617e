//! report.html in headless Chromium (Debian's `chromium`, which .ci/run installs): the page
//! loads with no console message and its screenshot is not blank.
//!
//! Runs when FLATCUT_CHROMIUM names the browser binary (as for crates/export's true-size test;
//! .ci/run sets it after installing Debian's chromium); FAILS if it is set but the binary is
//! missing; passes with a note when it is unset.

// Test helpers unwrap: a failure is a test failure with its message.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

use flatcut_pipeline::{Pipeline, RunOptions};

fn chromium() -> Option<PathBuf> {
    let bin = PathBuf::from(std::env::var_os("FLATCUT_CHROMIUM")?);
    assert!(
        bin.is_file(),
        "FLATCUT_CHROMIUM={} is not a file: install chromium or unset the variable",
        bin.display()
    );
    Some(bin)
}

/// Runs the bundled pipeline `name`, opens its report.html in headless Chromium and checks
/// that it loads with no console message and a screenshot that is not blank.
fn check_report(browser: &Path, name: &str) -> tiny_skia::Pixmap {
    let tmp = tempfile::tempdir().unwrap();
    let toml = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../pipelines/{name}.toml"));
    let out = tmp.path().join("o");
    flatcut_pipeline::run(
        &Pipeline::read(&toml).unwrap(),
        &RunOptions {
            out: Some(out.clone()),
            quiet: true,
            ..Default::default()
        },
    )
    .unwrap();
    let shot = tmp.path().join("shot.png");
    let page = format!("file://{}", out.join("report.html").display());
    let run = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=1200,1600",
        ])
        .arg(format!(
            "--user-data-dir={}",
            tmp.path().join("profile").display()
        ))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(&page)
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{name}: chromium failed: {log}");
    // Chromium logs every console message (errors, uncaught exceptions) as `:CONSOLE`.
    let console: Vec<&str> = log.lines().filter(|l| l.contains(":CONSOLE")).collect();
    assert!(console.is_empty(), "{name}: console messages: {console:#?}");
    // Non-blank: plenty of pixels that are not the white background, in several colours.
    let pm = tiny_skia::Pixmap::decode_png(&std::fs::read(&shot).unwrap()).unwrap();
    let px = pm.pixels();
    let inked = px
        .iter()
        .filter(|c| (c.red(), c.green(), c.blue()) != (255, 255, 255))
        .count();
    assert!(
        inked * 20 > px.len(),
        "{name}: only {inked} of {} pixels are not white",
        px.len()
    );
    let mut colours: Vec<(u8, u8, u8)> =
        px.iter().map(|c| (c.red(), c.green(), c.blue())).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(colours.len() > 50, "{name}: {} colours", colours.len());
    pm
}

#[test]
fn report_html_loads_in_headless_chromium_without_console_messages() {
    let Some(browser) = chromium() else {
        eprintln!("FLATCUT_CHROMIUM unset: report.html browser check skipped");
        return;
    };
    check_report(&browser, "patch-demo");
    // The main demo: its sheet is sheet.svg embedded as an image, with the 50 mm test square
    // filled pure blue (#0000ff), a colour nothing else on the page uses (the maps and
    // legends are viridis): blue pixels in the screenshot mean the embedded sheet rendered
    // (its red cut lines are 0.01 mm hairlines, too thin to count at page scale).
    let pm = check_report(&browser, "wetsuit-demo");
    let blue = pm
        .pixels()
        .iter()
        .filter(|c| c.blue() > 200 && c.red() < 60 && c.green() < 60)
        .count();
    assert!(
        blue > 50,
        "wetsuit-demo: {blue} blue pixels: the sheet did not render"
    );
}
