//! Random bytes and random mutations of the valid fixtures never make a reader panic.

#![allow(clippy::unwrap_used)] // helpers outside #[test] fns unwrap too

use std::path::PathBuf;

use flatcut_io::{Format, Units, read_mesh_from_bytes};
use proptest::prelude::*;

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../fixtures/valid")
            .join(name),
    )
    .unwrap()
}

const FIXTURES: &[(&str, Format)] = &[
    ("quad_groups.obj", Format::Obj),
    ("shuffled_ascii.ply", Format::Ply),
    ("shuffled_le.ply", Format::Ply),
    ("shuffled_be.ply", Format::Ply),
    ("two_facets_ascii.stl", Format::Stl),
    ("solid_header_binary.stl", Format::Stl),
    ("datauri.gltf", Format::Gltf),
    ("transform.glb", Format::Glb),
];

const FORMATS: [Format; 5] = [
    Format::Obj,
    Format::Ply,
    Format::Stl,
    Format::Gltf,
    Format::Glb,
];

#[derive(Clone, Debug)]
enum Mutation {
    Flip(usize, u8),
    Truncate(usize),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    /// Replaces a digit by another digit: keeps text formats parseable while changing
    /// counts, indices and offsets (reaches deeper than random bytes in JSON and headers).
    Digit(usize, u8),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Flip(i, b)),
        1 => any::<usize>().prop_map(Mutation::Truncate),
        2 => (any::<usize>(), prop::collection::vec(any::<u8>(), 1..8)).prop_map(|(i, v)| Mutation::Insert(i, v)),
        1 => (any::<usize>(), 1usize..16).prop_map(|(i, n)| Mutation::Delete(i, n)),
        4 => (any::<usize>(), any::<u8>()).prop_map(|(i, d)| Mutation::Digit(i, d)),
    ]
}

fn apply(mut data: Vec<u8>, muts: &[Mutation]) -> Vec<u8> {
    for m in muts {
        let len = data.len().max(1);
        match m {
            Mutation::Flip(i, b) => {
                if !data.is_empty() {
                    data[i % len] ^= b | 1;
                }
            }
            Mutation::Truncate(i) => data.truncate(i % len),
            Mutation::Insert(i, v) => {
                let at = i % (data.len() + 1);
                data.splice(at..at, v.iter().copied());
            }
            Mutation::Digit(i, d) => {
                let digits: Vec<usize> = (0..data.len())
                    .filter(|&k| data[k].is_ascii_digit())
                    .collect();
                if !digits.is_empty() {
                    data[digits[i % digits.len()]] = b'0' + d % 10;
                }
            }
            Mutation::Delete(i, n) => {
                let at = i % len;
                let end = (at + n).min(data.len());
                if at < end {
                    data.drain(at..end);
                }
            }
        }
    }
    data
}

fn check(bytes: &[u8], format: Format) {
    // Errors are fine; panics are not. A success must be a valid mesh.
    if let Ok(m) = read_mesh_from_bytes(bytes, format, "fuzz", Units::Mm) {
        m.mesh.validate().unwrap();
        assert!(!m.mesh.faces.is_empty());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600), prefix in 0usize..6) {
        // Also start random data with each format's magic so that the deeper code runs.
        let magic: &[&[u8]] = &[b"", b"ply\nformat binary_little_endian 1.0\n", b"solid x\nfacet", b"glTF\x02\0\0\0", b"v 1 2 3\nf ", b"{\"asset\":"];
        let mut data = magic[prefix].to_vec();
        data.extend_from_slice(&bytes);
        for f in FORMATS {
            check(&data, f);
        }
    }

    #[test]
    fn mutated_fixtures_never_panic(which in 0usize..FIXTURES.len(), muts in prop::collection::vec(mutation(), 1..6)) {
        let (name, format) = FIXTURES[which];
        let data = apply(fixture(name), &muts);
        check(&data, format);
    }
}

/// Every reader on every mutated fixture kind: 256 cases per format.
#[test]
fn mutated_fixtures_per_format() {
    use proptest::test_runner::{Config, TestRunner};
    for (name, format) in FIXTURES {
        let original = fixture(name);
        let mut runner = TestRunner::new(Config {
            cases: 256,
            failure_persistence: None,
            ..Config::default()
        });
        runner
            .run(&prop::collection::vec(mutation(), 1..4), |muts| {
                check(&apply(original.clone(), &muts), *format);
                Ok(())
            })
            .unwrap();
    }
}
