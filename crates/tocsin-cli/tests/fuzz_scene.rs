//! A seeded fuzzer for scene files, run by `make test` in bounded time: a valid JSON and a
//! valid TOML scene, mutated (bytes changed, ranges cut or repeated, awkward tokens inserted),
//! run by the `tocsin` binary, which must answer with status 0 or a one-line error and status
//! 2: never a panic (101), a signal or a hang. `TOCSIN_FUZZ_CASES` sets the cases per seed
//! (default 150; 5,000 per seed found nothing after the hardening issue's fixes).

#![allow(clippy::unwrap_used, clippy::panic)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::process::Command;

const JSON: &str = r#"{"meshes": {"a": "builtin:box", "p": "builtin:plate"},
 "queries": [
  {"query": "distance", "mesh1": "a", "mesh2": "p", "pose2": [0, 0, 2], "relative_error": 0.1},
  {"query": "collide", "mesh1": "a", "mesh2": "a", "pose1": [0, 0, 0, 0, 0, 0.3], "pose2": [0.5, 0, 0]},
  {"query": "within", "mesh1": "a", "mesh2": "a", "pose2": [2, 0, 0], "threshold": 1.5},
  {"query": "contact_time", "mesh1": "a", "mesh2": "a", "tolerance": 0.001, "max_iterations": 50,
   "motion1": {"kind": "interp", "start": [-3, 0, 0], "end": [3, 0, 0, 0, 0, 1], "center": [0, 0, 0]}},
  {"query": "motion_is_free", "mesh1": "a", "mesh2": "a", "max_iterations": 50,
   "motion1": {"kind": "translation", "start": [-3, 0, 0], "end": [3, 0, 2]}}]}"#;

const TOML: &str = r#"[meshes]
a = "builtin:box"
[[queries]]
query = "distance"
mesh1 = "a"
mesh2 = "a"
pose2 = [2.0, 0.0, 0.0]
[[queries]]
query = "contact_time"
mesh1 = "a"
mesh2 = "a"
motion1 = { kind = "screw", start = [-3.0, 0.0, 0.0], end = [3.0, 0.0, 0.0, 0.0, 0.0, 1.0] }
"#;

const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-1",
    "1e400",
    "-1e400",
    "1e-400",
    "0",
    "null",
    "true",
    "\"\"",
    "[]",
    "{}",
    "[1e308, 1e308, 1e308]",
    "\"builtin:nothing\"",
    "\"/no/such/file.obj\"",
    ",",
    ":",
    "\"a\"",
    "\"query\": \"distance\"",
    "18446744073709551616",
    "\u{feff}",
    "\"kind\": \"screw\"",
];

fn mutate(rng: &mut ChaCha8Rng, text: &str) -> Vec<u8> {
    let mut data = text.as_bytes().to_vec();
    for _ in 0..rng.random_range(1..=4) {
        let n = data.len();
        match rng.random_range(0..5) {
            0 if n > 0 => {
                let i = rng.random_range(0..n);
                data[i] = rng.random_range(32..127);
            }
            1 if n > 0 => {
                let a = rng.random_range(0..n);
                let b = (a + rng.random_range(0..=12)).min(n);
                data.drain(a..b);
            }
            2 if n > 0 => {
                let a = rng.random_range(0..n);
                let b = (a + rng.random_range(0..=40)).min(n);
                let piece = data[a..b].to_vec();
                let at = rng.random_range(0..=data.len());
                data.splice(at..at, piece);
            }
            _ => {
                let t = TOKENS[rng.random_range(0..TOKENS.len())];
                // Most often in place of a number, else anywhere.
                let numbers: Vec<usize> = (0..n)
                    .filter(|&i| {
                        data[i].is_ascii_digit() && (i == 0 || !data[i - 1].is_ascii_digit())
                    })
                    .collect();
                let at = if !numbers.is_empty() && rng.random_bool(0.7) {
                    numbers[rng.random_range(0..numbers.len())]
                } else {
                    rng.random_range(0..=n)
                };
                let end = (at..n)
                    .find(|&j| !data[j].is_ascii_digit() && data[j] != b'.')
                    .unwrap_or(n);
                data.splice(at..end.max(at), t.bytes());
            }
        }
    }
    data
}

#[test]
fn mutated_scenes_answer_or_fail_cleanly() {
    let cases: usize = std::env::var("TOCSIN_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(150);
    let dir = std::env::temp_dir().join(format!("tocsin-fuzz-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (s, (ext, seed)) in [("json", JSON), ("toml", TOML)].into_iter().enumerate() {
        let mut rng = ChaCha8Rng::seed_from_u64(2000 + s as u64);
        for k in 0..=cases {
            // Case 0 is the seed itself, which must succeed.
            let data = if k == 0 {
                seed.as_bytes().to_vec()
            } else {
                mutate(&mut rng, seed)
            };
            let path = dir.join(format!("scene.{ext}"));
            std::fs::write(&path, &data).unwrap();
            let out = Command::new(env!("CARGO_BIN_EXE_tocsin"))
                .args(["run", path.to_str().unwrap()])
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            let code = out.status.code();
            let what = format!("{ext} case {k}: {:?}", String::from_utf8_lossy(&data));
            assert!(
                matches!(code, Some(0) | Some(2)),
                "{what}: status {code:?}, {err}"
            );
            if k == 0 {
                assert_eq!(code, Some(0), "{what}: {err}");
            }
            if code == Some(2) {
                assert_eq!(err.trim_end().lines().count(), 1, "{what}: {err}");
                assert!(err.starts_with("tocsin: "), "{what}: {err}");
            } else {
                serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap();
            }
        }
    }
}
