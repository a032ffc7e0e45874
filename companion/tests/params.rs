//! The companion's parameters as one set (`--param`, `--params FILE`, `--check`), and the
//! commands docs/companion.md shows, run as written.

use std::process::{Command, Output};

const BINARY: &str = env!("CARGO_BIN_EXE_twocars-companion");

fn run(args: &[&str]) -> Output {
    Command::new(BINARY).args(args).output().unwrap()
}

/// The value of `name` in a `--check` listing.
fn listed(out: &Output, name: &str) -> Option<f32> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|line| {
            let (n, v) = line.split_once(' ')?;
            (n == name).then(|| v.parse().ok())?
        })
}

#[test]
fn limits_are_taken_as_a_set_in_any_order() {
    // TC_W_PM = 0.47 alone is below the default TC_W_EM = 1: set one at a time in this
    // order, the first one was refused. As a set, any order is valid.
    let limits = ["TC_V_PM=2.99", "TC_W_PM=0.47", "TC_V_EM=1.5", "TC_W_EM=0.3"];
    for order in [[0, 1, 2, 3], [3, 2, 1, 0], [1, 3, 0, 2]] {
        let mut args = vec!["--check"];
        for i in order {
            args.extend(["--param", limits[i]]);
        }
        let out = run(&args);
        assert!(
            out.status.success(),
            "{order:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(listed(&out, "TC_W_PM"), Some(0.47), "{order:?}");
        assert_eq!(listed(&out, "TC_W_EM"), Some(0.3), "{order:?}");
    }
}

#[test]
fn a_params_file_is_read_and_a_param_overrides_it() {
    let dir = std::env::temp_dir().join(format!("twocars-companion-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("unit.parm");
    std::fs::write(
        &file,
        "# the rover pair\nTC_V_PM 2.99\nTC_W_PM,0.47\n\nTC_V_EM  1.5  # slower\nTC_W_EM 0.3\n",
    )
    .unwrap();
    let path = file.to_str().unwrap();
    let out = run(&["--check", "--params", path, "--param", "TC_V_PM=3.2"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(listed(&out, "TC_V_PM"), Some(3.2));
    assert_eq!(listed(&out, "TC_V_EM"), Some(1.5));
    std::fs::write(&file, "TC_V_PM\n").unwrap();
    let out = run(&["--check", "--params", path]);
    assert!(!out.status.success());
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("line 1: not NAME VALUE"), "{said}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_refused_value_is_named() {
    let out = run(&[
        "--check",
        "--param",
        "TC_BOGUS=1",
        "--param",
        "TC_TIMEOUT=100",
        "--param",
        "TC_V_PM=3",
    ]);
    assert!(!out.status.success());
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("TC_BOGUS = 1: TC: no such parameter"),
        "{said}"
    );
    assert!(
        said.contains("TC_TIMEOUT = 100: TC: parameter out of range"),
        "{said}"
    );
    assert!(out.stdout.is_empty(), "nothing listed after a refusal");
    let out = run(&["--check", "--param", "TC_TGT_LAG=2"]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("TC_TGT_LAG = 2, TC_LEAD = 0, TC_TIMEOUT = 1: TC: lag and lead"),
        "{said}"
    );
}

/// Each `twocars-companion ...` line of docs/companion.md's examples, with `--check`: the
/// arguments and parameters as written are accepted (the link itself is not opened).
#[test]
fn the_documented_commands_run_as_written() {
    let doc = include_str!("../../docs/companion.md");
    let commands: Vec<&str> = doc
        .lines()
        .filter_map(|line| line.trim().strip_prefix("twocars-companion "))
        .map(|rest| rest.split('#').next().unwrap_or("").trim())
        .collect();
    assert!(commands.len() >= 3, "{commands:?}");
    for command in commands {
        let mut args: Vec<&str> = command.split_whitespace().collect();
        args.push("--check");
        // As a reader runs them: from the repository's root.
        let out = Command::new(BINARY)
            .args(&args)
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "twocars-companion {command}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
