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
