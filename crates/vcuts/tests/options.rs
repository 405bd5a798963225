//! Every number an option takes is checked as the command line is read, against the range the
//! options table states (`vcuts::options::NUMBERS`, `docs/options.md`): each option of each
//! command that has it is parsed through the real command line at its ends, just past them, and
//! with NaN, infinities, an empty and a malformed value.

use clap::{CommandFactory, Parser};
use vcut_scene::limits::End;
use vcuts::Cli;
use vcuts::options::{Number, OptionRow, table};

/// A command line for `row`'s command with `--option value`, every required argument given.
fn argv(cli: &clap::Command, row: &OptionRow, value: &str) -> Vec<String> {
    let mut argv = vec!["vcuts".to_string()];
    let mut cmd = cli;
    for name in row.command.split_whitespace() {
        argv.push(name.into());
        cmd = cmd.find_subcommand(name).unwrap();
        for a in cmd.get_arguments().filter(|a| a.is_required_set()) {
            match a.get_long() {
                Some(long) if format!("--{long}") != row.option => {
                    let n = vcuts::options::number(long);
                    argv.extend([format!("--{long}"), inside(&n)]);
                }
                Some(_) => {}
                None => argv.push("x.vcuts".into()),
            }
        }
    }
    if row.command.is_empty() {
        argv.extend(["inspect".into(), "builtin:teapot".into()]);
    }
    argv.extend([row.option.clone(), value.into()]);
    argv
}

/// A value well inside the range.
fn inside(n: &Number) -> String {
    let v = match (n.limit.low, n.limit.high) {
        (End::Closed(l) | End::Open(l), End::Closed(h) | End::Open(h)) => l + (h - l) / 2.0,
        (End::Closed(l) | End::Open(l), End::None) => l + 1.0,
        (End::None, End::Closed(h) | End::Open(h)) => h - 1.0,
        (End::None, End::None) => 0.5,
    };
    if n.whole { (v.round() as u64).to_string() } else { v.to_string() }
}

/// Values to try and whether the range holds each.
fn probes(n: &Number) -> Vec<(String, bool)> {
    let mut out = vec![(inside(n), true)];
    for bad in ["nan", "inf", "-inf", "", "1,2", "abc", "0x10"] {
        out.push((bad.to_string(), false));
    }
    let step = |v: f64| if n.whole { 1.0 } else { (v.abs() * 1e-3).max(1e-3) };
    for (end, sign) in [(n.limit.low, -1.0), (n.limit.high, 1.0)] {
        match end {
            End::Closed(v) => out.extend([(v, true), (v + sign * step(v), false)].map(|(x, ok)| (fmt(n, x), ok))),
            End::Open(v) => out.extend([(v, false), (v - sign * step(v), true)].map(|(x, ok)| (fmt(n, x), ok))),
            End::None => {}
        }
    }
    if n.whole {
        out.push((format!("{}.5", inside(n)), false));
    }
    // A whole number below 0 is not written as one.
    out.retain(|(v, _)| !(n.whole && v.starts_with('-') && v != "-inf"));
    out
}

fn fmt(n: &Number, x: f64) -> String {
    if n.whole { format!("{}", x as i64) } else { format!("{x}") }
}

#[test]
fn every_number_is_refused_outside_its_range_and_taken_inside() {
    let cli = Cli::command();
    cli.clone().debug_assert();
    let rows: Vec<OptionRow> = table(&cli).into_iter().filter(|r| r.number.is_some()).collect();
    assert!(rows.len() >= 30, "only {} options take a number", rows.len());
    for row in &rows {
        let n = row.number.unwrap();
        for (value, ok) in probes(&n) {
            let line = argv(&cli, row, &value);
            match (Cli::try_parse_from(&line), ok) {
                (Ok(_), true) => {}
                (Err(e), false) => {
                    let text = e.to_string();
                    assert!(text.contains(&row.option), "the error does not name {}: {text}", row.option);
                }
                (Ok(_), false) => panic!("{} accepted {value:?} ({}): {}", row.option, n.describe(), line.join(" ")),
                (Err(e), true) => panic!("{} refused {value:?} ({}): {e}", row.option, n.describe()),
            }
        }
    }
    // Every entry of the table of numbers is an option of some command.
    for (name, _) in vcuts::options::NUMBERS {
        assert!(rows.iter().any(|r| r.option == format!("--{name}")), "--{name} is no command's option");
    }
}

#[test]
fn the_options_table_lists_every_command_and_its_ranges() {
    let md = vcuts::options::markdown(&Cli::command());
    for part in [
        "## `vcuts render`",
        "## `vcuts leaves`",
        "## `vcuts farm slurm`",
        "| `--width` | WIDTH | a whole number in [1, 16384] pixels | 640 |",
        "| `--light-error` | REL | a number in (0, 1) (relative",
        "| `--mode` |",
        "| `--threads` | N | a whole number in [1, 4096] threads |",
    ] {
        assert!(md.contains(part), "no {part:?} in:\n{md}");
    }
}
