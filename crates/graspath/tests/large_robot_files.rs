//! Large generated MJCF and SRDF files parse, in time linear in their size: lines are counted
//! in one pass and names and attributes are checked for repeats through hash sets. Each check
//! reads a file of N elements and one of 4N (a few MB) and asserts that the larger takes less
//! than 10 times as long (linear work gives about 4, the quadratic reading this replaces 16),
//! counting the smaller as at least 50 ms; each time is the best of three runs, so a busy
//! machine does not fail the test. Times are printed.

use graspath::robot::{MjcfRobot, Srdf};
use std::fmt::Write as _;
use std::path::Path;
use std::time::{Duration, Instant};

/// The best of three runs of `f`.
fn best_of_three(mut f: impl FnMut()) -> Duration {
    (0..3)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed()
        })
        .min()
        .unwrap()
}

/// Times `parse` on `make(n)` and `make(4n)` and checks the growth is not quadratic.
fn assert_linear(what: &str, n: usize, make: impl Fn(usize) -> String, parse: impl Fn(&str)) {
    let small = make(n);
    let large = make(4 * n);
    let t1 = best_of_three(|| parse(&small));
    let t4 = best_of_three(|| parse(&large));
    let ratio = t4.as_secs_f64() / t1.as_secs_f64().max(1e-6);
    eprintln!(
        "{what}: {} bytes in {t1:?}, {} bytes in {t4:?} (ratio {ratio:.1})",
        small.len(),
        large.len()
    );
    // A floor of 50 ms for the small file keeps timer noise and a busy machine out of the
    // ratio (the quadratic reading took seconds on these sizes).
    assert!(
        t4.as_secs_f64() < 10.0 * t1.as_secs_f64().max(0.05),
        "{what}: 4x the input took {ratio:.1}x the time ({t1:?} -> {t4:?})"
    );
}

/// An MJCF robot of `n` bodies: a default class per ten bodies, each body with a named hinge,
/// two named geoms and a motor, and a chain of six bodies at the end.
fn mjcf(n: usize) -> String {
    let mut s = String::from("<mujoco model=\"large\">\n<default>\n");
    for c in 0..n / 10 + 1 {
        let _ = writeln!(
            s,
            "  <default class=\"c{c}\"><joint axis=\"0 1 0\" range=\"-90 90\"/><geom type=\"capsule\" size=\"0.02 0.05\" euler=\"0 {c} 0\"/></default>"
        );
    }
    s.push_str("</default>\n<worldbody>\n");
    for b in 0..n {
        let _ = writeln!(
            s,
            "  <body name=\"b{b}\" pos=\"0 0 0.1\" childclass=\"c{}\">\n    <joint name=\"j{b}\"/>\n    <geom name=\"g{b}\" quat=\"1 0 0 0\"/>\n    <geom name=\"h{b}\" type=\"sphere\" size=\"0.01\"/>\n  </body>",
            b / 10
        );
    }
    s.push_str("  <body name=\"arm0\">");
    for k in 1..=6 {
        let _ = write!(
            s,
            "<body name=\"arm{k}\" pos=\"0 0 0.1\"><joint name=\"arm_j{k}\" axis=\"0 1 0\" range=\"-1 1\"/><geom size=\"0.01\"/>"
        );
    }
    s.push_str(&"</body>".repeat(7));
    s.push_str("\n</worldbody>\n<actuator>\n");
    for b in 0..n {
        let _ = writeln!(s, "  <motor joint=\"j{b}\" forcerange=\"-10 10\"/>");
    }
    s.push_str("</actuator>\n</mujoco>\n");
    s
}

fn parse_mjcf(text: &str) {
    let robot = MjcfRobot::from_xml_in(text, "large.xml", Path::new(".")).unwrap();
    let chain = robot.chain("world", "arm6", None).unwrap();
    assert_eq!(chain.dof(), 6);
}

#[test]
fn a_large_mjcf_file_parses_in_linear_time() {
    assert_linear("MJCF bodies", 2_500, mjcf, parse_mjcf);
}

/// An SRDF of `n` `<disable_collisions>` pairs, as MoveIt's setup assistant writes them.
fn srdf(n: usize) -> String {
    let mut s = String::from(
        "<?xml version=\"1.0\"?>\n<robot name=\"large\">\n  <group name=\"arm\">\n    <chain base_link=\"l0\" tip_link=\"l9\"/>\n  </group>\n",
    );
    for k in 0..n {
        let _ = writeln!(
            s,
            "  <disable_collisions link1=\"l{}\" link2=\"l{}\" reason=\"Never\"/>",
            k % 50,
            (k / 50) % 50
        );
    }
    s.push_str("</robot>\n");
    s
}

#[test]
fn a_large_srdf_file_parses_in_linear_time() {
    let links: Vec<String> = (0..50).map(|k| format!("l{k}")).collect();
    assert_linear("SRDF pairs", 20_000, srdf, |text| {
        let srdf = Srdf::parse(text, "large.srdf").unwrap();
        srdf.check_links(&links).unwrap();
        let last = srdf.disabled.last().unwrap();
        assert_eq!(last.line, srdf.disabled.len() + 5);
    });
}

/// One element with `n` attributes (quick-xml's own duplicate check compares every pair).
fn many_attributes(root: &str, element: &str, n: usize) -> String {
    let mut s = format!("<{root}><{element}");
    for k in 0..n {
        let _ = write!(s, " a{k}=\"{k}\"");
    }
    s.push_str(&format!("/></{root}>"));
    s
}

#[test]
fn an_element_with_many_attributes_parses_in_linear_time() {
    assert_linear(
        "MJCF attributes",
        20_000,
        |n| many_attributes("mujoco", "compiler", n).replace("</mujoco>", "<worldbody/></mujoco>"),
        |text| {
            MjcfRobot::from_xml_in(text, "attributes.xml", Path::new(".")).unwrap();
        },
    );
    assert_linear(
        "SRDF attributes",
        20_000,
        |n| many_attributes("robot", "group name=\"g\"", n),
        |text| {
            Srdf::parse(text, "attributes.srdf").unwrap();
        },
    );
    // A repeated attribute is still refused, with its name.
    let text = many_attributes("mujoco", "compiler", 100).replace("a99=", "a7=");
    let error = MjcfRobot::from_xml_in(&text, "twice.xml", Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("twice.xml:1") && error.contains("attribute `a7` is given twice"),
        "{error}"
    );
    let text = many_attributes("robot", "group name=\"g\"", 100).replace("a99=", "a7=");
    let error = Srdf::parse(&text, "twice.srdf").unwrap_err().to_string();
    assert!(error.contains("attribute `a7` is given twice"), "{error}");
}

/// `depth` nested default classes, each giving a geom many attributes, and `leaves` classes
/// inside the deepest one: copying every class's inherited attributes would cost
/// depth × attributes × leaves.
fn nested_defaults(depth: usize, leaves: usize) -> String {
    let mut s = String::from("<mujoco><default>");
    for d in 0..depth {
        let _ = write!(
            s,
            "<default class=\"d{d}\"><geom type=\"sphere\" size=\"0.0{}\" euler=\"0 0 {d}\" x{d}a=\"1\" x{d}b=\"2\" x{d}c=\"3\"/>",
            d % 9 + 1
        );
    }
    for leaf in 0..leaves {
        let _ = write!(
            s,
            "<default class=\"leaf{leaf}\"><joint range=\"-{leaf} {leaf}\"/></default>"
        );
    }
    s.push_str(&"</default>".repeat(depth));
    s.push_str("</default><worldbody><body name=\"b\">");
    for leaf in (0..leaves).step_by(97) {
        let _ = write!(s, "<geom class=\"leaf{leaf}\"/>");
    }
    s.push_str("</body></worldbody></mujoco>");
    s
}

#[test]
fn nested_default_classes_cost_a_bounded_amount_each() {
    // About 500 KB at N (the size that used to clone its classes to 4 GB), 2 MB at 4N: 400
    // nested classes, and 8,000 then 32,000 classes inside the deepest one.
    assert_linear(
        "MJCF nested defaults",
        8_000,
        |n| nested_defaults(400, n),
        |text| {
            let robot = MjcfRobot::from_xml_in(text, "defaults.xml", Path::new(".")).unwrap();
            let resolver = robot.mesh_resolver();
            let shapes = robot.collisions(&resolver).unwrap();
            // The geoms take the deepest geom class's sphere and size.
            assert!(!shapes.is_empty() && shapes[0].shapes.len() > 10);
        },
    );
}
