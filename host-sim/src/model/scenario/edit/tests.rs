//! Given/when/then checks of the key edits: an edit changes its key and nothing else, creates
//! what is missing, takes bare words as strings, and every malformed or misplaced edit is
//! refused with the key named.

use super::{apply_edits, KeyEdit};
use crate::model::scenario::{Scenario, ThrustKind};

fn x500_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("designs/x500/scenario.toml")
}

fn edits(list: &[&str]) -> Vec<KeyEdit> {
    list.iter().map(|s| s.parse().unwrap()).collect()
}

/// Given the committed x500 design, when its local `k_p` and `k_v` are set, then the edited
/// file parses to the original table with exactly those two values replaced (every other key,
/// float for float), and the scenario carries them.
#[test]
fn an_edit_changes_its_key_and_nothing_else() {
    let text = std::fs::read_to_string(x500_path()).unwrap();
    let e = edits(&["gains.local.kp=36", "gains.local.kv = 12.5"]);
    let edited: toml::Table = toml::from_str(&apply_edits(&text, &e).unwrap()).unwrap();
    let mut expected: toml::Table = toml::from_str(&text).unwrap();
    let local = expected["gains"]["local"].as_table().unwrap().clone();
    let mut local = local;
    local.insert("kp".into(), toml::Value::Integer(36));
    local.insert("kv".into(), toml::Value::Float(12.5));
    expected["gains"]
        .as_table_mut()
        .unwrap()
        .insert("local".into(), toml::Value::Table(local));
    assert_eq!(edited, expected);
    let s = Scenario::load_with_edits(&x500_path(), &e).unwrap();
    let l = s.gains.local.unwrap();
    assert_eq!((l.kp, l.kv), (36.0, 12.5));
}

/// Given the paper's scenario, when a missing table's key and a bare word are set, then the
/// table is created and the word is a string, and the scenario flies them.
#[test]
fn missing_tables_are_created_and_bare_words_are_strings() {
    let e = edits(&["controller.thrust=vertical-priority"]);
    assert_eq!(e[0].value, toml::Value::String("vertical-priority".into()));
    let paper = super::super::PAPER_SCENARIO;
    assert!(!toml::from_str::<toml::Table>(paper)
        .unwrap()
        .contains_key("controller"));
    let text = apply_edits(paper, &e).unwrap();
    let s = Scenario::parse(&text, "paper with an edit").unwrap();
    assert_eq!(s.controller.thrust, ThrustKind::VerticalPriority);
}

/// Given malformed or misplaced edits, when they are parsed or applied, then each is refused
/// with a message that names the problem: no `=`, an empty key, a value that is not TOML, a
/// path through a number, and (from the scenario's own check) a key the scenario does not have.
#[test]
fn bad_edits_are_refused_by_name() {
    let no_eq = "gains.kp".parse::<KeyEdit>().unwrap_err().to_string();
    assert!(no_eq.contains("TABLE.KEY=VALUE"), "{no_eq}");
    let empty = "gains..kp=1".parse::<KeyEdit>().unwrap_err().to_string();
    assert!(empty.contains("empty key"), "{empty}");
    let words = "trajectory.kind=two words"
        .parse::<KeyEdit>()
        .unwrap_err()
        .to_string();
    assert!(words.contains("not a TOML value"), "{words}");
    let text = std::fs::read_to_string(x500_path()).unwrap();
    let through = apply_edits(&text, &edits(&["gains.kp.x=1"]))
        .unwrap_err()
        .to_string();
    assert!(
        through.contains("gains.kp is a float, not a table"),
        "{through}"
    );
    let typo = Scenario::load_with_edits(&x500_path(), &edits(&["gains.local.kpp=1"]))
        .unwrap_err()
        .to_string();
    assert!(
        typo.contains("kpp") && typo.contains("gains.local.kpp=1"),
        "{typo}"
    );
}

/// Given the embedded paper scenario, when it is parsed with no edits, then it is the paper's
/// scenario itself (the default run stays bit for bit), and with an edit only the edited key
/// differs.
#[test]
fn no_edit_is_the_scenario_itself() {
    let paper = super::super::PAPER_SCENARIO;
    let plain = Scenario::parse_with_edits(paper, "paper", &[]).unwrap();
    assert_eq!(plain, Scenario::paper());
    let edited = Scenario::parse_with_edits(paper, "paper", &edits(&["gains.M_p=2"])).unwrap();
    assert_eq!(edited.gains.M_p, 2.0);
    let mut back = edited.clone();
    back.gains.M_p = plain.gains.M_p;
    assert_eq!(back, plain);
}
