//! The `tocsin` command end to end: JSON out, one-line errors with status 2.

#![allow(clippy::unwrap_used, clippy::panic)]

use std::process::Command;

fn tocsin(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_tocsin"))
        .args(args)
        .output()
        .expect("run tocsin");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn distance_prints_json() {
    let (code, out, _) = tocsin(&["distance", "builtin:box", "builtin:box", "--pose2", "2,0,0"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!((v["distance"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(v["point1"].as_array().unwrap().len(), 3);
}

#[test]
fn collide_and_within() {
    let (_, out, _) = tocsin(&[
        "collide",
        "builtin:box",
        "builtin:box",
        "--pose2",
        "0.5,0,0,0,0,0.3",
        "--pairs",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["collide"], true);
    assert!(!v["pairs"].as_array().unwrap().is_empty());
    let (_, out, _) = tocsin(&[
        "within",
        "builtin:box",
        "builtin:box",
        "--pose2",
        "1.5,0,0",
        "0.4",
    ]);
    assert_eq!(
        serde_json::from_str::<serde_json::Value>(&out).unwrap()["within"],
        false
    );
}

#[test]
fn contact_time_prints_json() {
    let (code, out, err) = tocsin(&[
        "contact-time",
        "builtin:box",
        "builtin:box",
        "--motion1",
        "translation:3,0,0:-1,0,0",
        "--tolerance",
        "1e-6",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["contact"], true);
    let t = v["time"].as_f64().unwrap();
    assert!(t <= 0.5 && t > 0.5 - 1e-6, "{t}");
    let (_, out, _) = tocsin(&[
        "contact-time",
        "builtin:box",
        "builtin:box",
        "--motion1",
        "screw:-3,0,2:3,0,2,0,0,1",
    ]);
    assert_eq!(
        serde_json::from_str::<serde_json::Value>(&out).unwrap()["contact"],
        false
    );
    let (code, out, _) = tocsin(&[
        "contact-time",
        "builtin:box",
        "builtin:box",
        "--motion1",
        "interp:-3,0,0:3,0,0,0,1,0:0.1,0,0",
    ]);
    assert_eq!(code, 0);
    assert_eq!(
        serde_json::from_str::<serde_json::Value>(&out).unwrap()["status"],
        "converged"
    );
}

fn scene_file(name: &str, text: &str) -> String {
    let dir = std::env::temp_dir().join(format!("tocsin-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

#[test]
fn scene_files_in_json_and_toml() {
    let json = r#"{ "meshes": { "a": "builtin:box", "k": "builtin:knot2.8k" },
      "queries": [
        { "query": "distance", "mesh1": "a", "mesh2": "a", "pose2": [2, 0, 0] },
        { "query": "collide", "mesh1": "a", "mesh2": "a", "pose2": [0.5, 0, 0, 0, 0, 0.3] },
        { "query": "within", "mesh1": "a", "mesh2": "a", "pose2": [1.5, 0, 0], "threshold": 0.4 },
        { "query": "contact_time", "mesh1": "a", "mesh2": "a", "tolerance": 1e-6,
          "motion1": { "kind": "translation", "start": [3, 0, 0], "end": [-1, 0, 0] } },
        { "query": "contact_time", "mesh1": "k", "mesh2": "k",
          "motion1": { "kind": "interp", "start": [-14, 1, 0.5], "end": [14, 0, 0, 0, 0, 1.2], "center": [0, 0, 0] } }
      ] }"#;
    let (code, out, err) = tocsin(&["run", &scene_file("s.json", json)]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let r = v["results"].as_array().unwrap();
    assert_eq!(r.len(), 5);
    assert!((r[0]["distance"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(r[1]["collide"], true);
    assert_eq!(r[2]["within"], false);
    let t = r[3]["time"].as_f64().unwrap();
    assert!(t <= 0.5 && t > 0.5 - 1e-6);
    assert_eq!(r[4]["contact"], true);
    let toml = r#"
[meshes]
a = "builtin:box"

[[queries]]
query = "distance"
mesh1 = "a"
mesh2 = "a"
pose2 = [0, 3, 0]
"#;
    let (code, out, err) = tocsin(&["run", &scene_file("s.toml", toml)]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!((v["results"][0]["distance"].as_f64().unwrap() - 2.0).abs() < 1e-12);
}

#[test]
fn bad_scenes_are_one_line_and_status_2() {
    for (name, text, expect) in [
        (
            "m.json",
            r#"{ "meshes": {}, "queries": [ { "query": "collide", "mesh1": "x", "mesh2": "x" } ] }"#,
            "no mesh named `x`",
        ),
        (
            "p.json",
            r#"{ "meshes": { "a": "builtin:box" }, "queries": [ { "query": "collide", "mesh1": "a", "mesh2": "a", "pose2": [1, 2] } ] }"#,
            "query 0 pose2",
        ),
        (
            "u.json",
            r#"{ "meshes": { "a": "builtin:box" }, "queries": [ { "query": "teleport", "mesh1": "a" } ] }"#,
            "unknown variant",
        ),
        (
            "f.json",
            r#"{ "meshes": { "a": "/no/such.obj" }, "queries": [] }"#,
            "mesh `a`",
        ),
        ("t.toml", "[meshes\n", "t.toml"),
    ] {
        let (code, out, err) = tocsin(&["run", &scene_file(name, text)]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(out.is_empty());
        assert_eq!(err.trim().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(expect), "{name}: {err}");
    }
    let (code, _, err) = tocsin(&["run", "/no/such/scene.json"]);
    assert_eq!(code, 2);
    assert!(err.contains("cannot read"));
}

#[test]
fn render_contact_writes_a_png() {
    let out = std::env::temp_dir().join(format!("tocsin-render-{}.png", std::process::id()));
    let out = out.to_string_lossy().into_owned();
    let (code, stdout, err) = tocsin(&[
        "render-contact",
        "builtin:knot2.8k",
        "builtin:knot2.8k",
        "--motion1",
        "screw:-14,1,0.5:14,0,0,0,0,1.2",
        "--out",
        &out,
        "--size",
        "320",
        "240",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    assert_eq!(v["contact"], true);
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    // Width and height from the IHDR chunk.
    assert_eq!(u32::from_be_bytes(bytes[16..20].try_into().unwrap()), 320);
    assert_eq!(u32::from_be_bytes(bytes[20..24].try_into().unwrap()), 240);
    assert!(bytes.len() > 2000, "the picture has content");
}

#[test]
fn bad_input_is_one_line_and_status_2() {
    for args in [
        vec!["distance", "/no/such.obj", "builtin:box"],
        vec!["distance", "builtin:box", "builtin:nope"],
        vec!["distance", "builtin:box", "builtin:box", "--pose2", "1,2"],
        vec![
            "distance",
            "builtin:box",
            "builtin:box",
            "--pose2",
            "2,0,0,0,0,0,0,2,0,0,0,0,0,0,0,1",
        ],
        vec!["distance", "builtin:box", "builtin:box", "--pose1", "a,b,c"],
        vec!["within", "builtin:box", "builtin:box", "--", "-1"],
        vec![
            "contact-time",
            "builtin:box",
            "builtin:box",
            "--motion1",
            "translation:0,0,0:1,0,0,0,0,1",
        ],
        vec![
            "contact-time",
            "builtin:box",
            "builtin:box",
            "--motion1",
            "wobble:0,0,0:1,0,0",
        ],
        vec![
            "contact-time",
            "builtin:box",
            "builtin:box",
            "--tolerance",
            "0",
        ],
    ] {
        let (code, out, err) = tocsin(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty());
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("tocsin: "), "{err}");
    }
}
