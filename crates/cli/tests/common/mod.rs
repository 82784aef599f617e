//! Helpers shared by the CLI tests: the built `flatcut` binary, run to success.
#![allow(dead_code, clippy::unwrap_used)]

use std::process::{Command, Output};

/// A command running the `flatcut` binary cargo built for these tests.
pub fn flatcut() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flatcut"))
}

/// Runs `cmd`, which must exit successfully (else the test fails showing its stderr).
pub fn succeed(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// [`succeed`], with its standard output parsed as JSON.
pub fn succeed_json(cmd: &mut Command) -> serde_json::Value {
    serde_json::from_slice(&succeed(cmd).stdout).unwrap()
}

/// Runs `flatcut` with `args`, which must fail with exit code 1 (else the test fails); its
/// standard error.
pub fn refused<I, S>(args: I) -> String
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    let out = flatcut().args(args).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(1), "{err}");
    err
}
