//! The numbers the commands take, each with its range, and the table of every option.
//!
//! [`NUMBERS`] names each option that takes a number (by its long name: an option of that name
//! means the same in every command) with its [`Limit`]; the option's value parser is built from
//! that entry ([`real`], [`real64`], [`whole`]), so what the parser accepts and what the table
//! says cannot drift apart. The options of the frame's settings (`vcut_shade::FrameArgs`) parse
//! with the limits of `vcut_shade::settings`, which the entries here name; `tests/options.rs`
//! parses every entry at and past its ends through the real command line, those included.
//!
//! [`table`] walks the command line's definition (clap) and lists every option of every
//! command with its value, range or choices, default and help: `cargo xtask publish` writes it
//! to `docs/options.md`, and the command-line fuzz target draws its options from it.

use vcut_data::params;
use vcut_scene::limits::Limit;
use vcut_shade::frame::settings;

/// A number an option takes: its range, and whether it is a whole number.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Number {
    /// The range.
    pub limit: Limit,
    /// A whole number (a count, pixels).
    pub whole: bool,
}

impl Number {
    const fn real(limit: Limit) -> Number {
        Number { limit, whole: false }
    }

    const fn whole(limit: Limit) -> Number {
        Number { limit, whole: true }
    }

    /// What the number may be, as the table and the errors say it.
    pub fn describe(&self) -> String {
        let d = self.limit.describe();
        if self.whole { format!("a whole {}", d.trim_start_matches("a ")) } else { d }
    }
}

/// A count from `low` to `high`.
const fn count(low: f64, high: f64, unit: &'static str) -> Number {
    Number::whole(Limit::within(low, high, unit))
}

/// Every option that takes a number, by long name, with its range.
pub const NUMBERS: &[(&str, Number)] = &[
    // Every command.
    ("threads", count(1.0, 4096.0, "threads")),
    ("estimate-seconds", Number::real(crate::resources::ESTIMATE_SECONDS)),
    // Images.
    ("width", Number::whole(crate::values::SIDE)),
    ("height", Number::whole(crate::values::SIDE)),
    ("exposure", Number::real(crate::values::EXPOSURE)),
    ("env-rotation", Number::real(crate::values::ENV_ROTATION)),
    ("live-move-ms", Number::real(crate::values::LIVE_MOVE_MS)),
    ("frames", count(1.0, 1e12, "frames")),
    // The frame's settings (`vcut_shade::FrameArgs`).
    ("light-error", Number::real(vcut_scene::check::LIGHT_ERROR)),
    ("light-max-leaves", Number::whole(settings::LIGHT_MAX_LEAVES)),
    ("memory-budget", Number::real(settings::BUDGET_MB)),
    ("field-reach", Number::real(settings::REACH)),
    // Precompute.
    ("svc-max-error", Number::real(params::SVC_MAX_ERROR)),
    ("field-spheres", Number::whole(params::FIELD_SPHERES)),
    ("field-resolution", Number::whole(params::FIELD_RESOLUTION)),
    ("field-max-error", Number::real(params::FIELD_MAX_ERROR)),
    ("plan", count(1.0, 1_000_000.0, "shards")),
    ("shards", count(1.0, 1_000_000.0, "shards")),
    ("max-running", count(1.0, 1_000_000.0, "tasks")),
    ("cpus-per-task", count(1.0, 4096.0, "CPUs")),
    // Directions.
    ("n", count(4.0, (1u64 << 22) as f64, "directions")),
    ("wedges", count(1.0, (1u64 << 21) as f64, "wedges")),
    ("bands", count(0.0, (1u64 << 21) as f64, "bands")),
    // Inspect.
    ("weld", Number::real(vcut_scene::check::WELD)),
    // Leaves.
    ("leaf-count", count(1.0, 1_000_000.0, "leaves")),
    ("vertices", count(1.0, 100_000_000.0, "vertices")),
    ("time-of-day", Number::real(crate::leaves::plant::HOURS)),
    ("sun-diameter", Number::real(crate::leaves::plant::SUN_DIAMETER)),
    ("lvc-resolution", count(1.0, 1024.0, "texels a face side")),
    ("prt-rays", count(1.0, 1_000_000.0, "rays")),
    ("sun-edge-rays", count(0.0, 4096.0, "rays")),
    ("bounces", count(0.0, 64.0, "bounces")),
    ("thickness", Number::real(crate::leaves::plant::THICKNESS)),
    ("reference-paths", count(1.0, 1_000_000.0, "paths a vertex")),
    ("reference-vertices", count(1.0, 100_000_000.0, "vertices")),
];

/// The values of options that are not a number in a range, as their own parsers check them.
pub const OTHER_VALUES: &[(&str, &str)] = &[
    ("directions", "a power of two from 64 to 65,536"),
    ("flat-edge-leaves", "a power of two (1: exact), or `interactive`"),
    ("field-reach", "or `outermost`"),
    ("move", "NAME=DX,DY,DZ: finite, and a place where f32 keeps the object's shape (to 2^-12 of its radius)"),
    ("turn", "NAME=DEGREES: finite; the file needs a symmetric direction set (`turn_steps`)"),
    ("brdf", "NAME=MODEL[:KEY=VALUE,...]: kd, ks in [0, 1]; exponent ≥ 0; roughness in (0, 1]"),
    ("size", "WIDTHxHEIGHT, each a whole number in [1, 16384] pixels"),
    ("sun", "ELEVATION,AZIMUTH: two finite numbers of degrees"),
    ("reflectance", "R,G,B (or one for all three): finite, at least 0"),
    ("transmittance", "R,G,B (or one for all three): finite, at least 0"),
    ("sigma-a", "R,G,B (or one for all three): finite, at least 0, per mm"),
    ("sigma-s", "R,G,B (or one for all three): finite, at least 0, per mm"),
    ("gloss-top", "RHO_S,ROUGHNESS: ρ_s at least 0, roughness above 0"),
    ("gloss-bottom", "RHO_S,ROUGHNESS: ρ_s at least 0, roughness above 0"),
];

/// The entry of option `--long`. Every option parsed with [`real`], [`real64`] or [`whole`] has
/// one: a name missing here fails as the command line is built (every test that parses one).
pub fn number(long: &str) -> Number {
    match NUMBERS.iter().find(|(name, _)| *name == long) {
        Some((_, n)) => *n,
        None => panic!("--{long} has no entry in vcuts::options::NUMBERS"),
    }
}

/// The value parser of real-number option `--long` (f32, checked as the f32 it becomes).
pub fn real(long: &'static str) -> impl Fn(&str) -> Result<f32, String> + Clone + Send + Sync + 'static {
    let n = number(long);
    move |s| n.limit.parse_f32(s)
}

/// The value parser of real-number option `--long` (f64).
pub fn real64(long: &'static str) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    let n = number(long);
    move |s| n.limit.parse(s)
}

/// The value parser of whole-number option `--long`.
pub fn whole<T>(long: &'static str) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: TryFrom<u64>,
{
    let n = number(long);
    move |s| {
        let v = n.limit.parse_whole(s)?;
        T::try_from(v).map_err(|_| format!("{s:?}: must be {}", n.describe()))
    }
}

/// One option of one command, as the table shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionRow {
    /// The command (`render`; `farm slurm` for a nested one; empty for the global options).
    pub command: String,
    /// `--width`.
    pub option: String,
    /// What it takes (`WIDTH`; empty for a switch).
    pub value: String,
    /// Its range ([`NUMBERS`]) or choices; empty where it takes a path or text.
    pub range: String,
    /// Its default, if it has one.
    pub default: String,
    /// Its help, on one line.
    pub help: String,
    /// The number it takes, if it takes one.
    pub number: Option<Number>,
    /// The choices it takes, if it takes named ones.
    pub choices: Vec<String>,
}

/// Every option of every command of `cli` (from `Cli::command()`), in the order `--help` lists
/// them; the global options once, under an empty command.
pub fn table(cli: &clap::Command) -> Vec<OptionRow> {
    let mut rows = Vec::new();
    rows.extend(cli.get_arguments().filter(|a| a.is_global_set()).filter_map(|a| row("", a)));
    for sub in cli.get_subcommands() {
        commands(sub, sub.get_name().to_string(), &mut rows);
    }
    rows
}

fn commands(cmd: &clap::Command, name: String, rows: &mut Vec<OptionRow>) {
    rows.extend(cmd.get_arguments().filter(|a| !a.is_global_set()).filter_map(|a| row(&name, a)));
    for sub in cmd.get_subcommands() {
        commands(sub, format!("{name} {}", sub.get_name()), rows);
    }
}

/// The row of option `arg` (`None` for positionals, help and version).
fn row(command: &str, arg: &clap::Arg) -> Option<OptionRow> {
    let long = arg.get_long()?;
    if matches!(long, "help" | "version") || arg.is_hide_set() {
        return None;
    }
    let takes = arg.get_action().takes_values();
    let value = if takes {
        arg.get_value_names().map(|v| v.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(" ")).unwrap_or_default()
    } else {
        String::new()
    };
    let number = NUMBERS.iter().find(|(name, _)| *name == long).map(|(_, n)| *n).filter(|_| takes);
    let choices: Vec<String> =
        if takes { arg.get_possible_values().iter().map(|p| p.get_name().to_string()).collect() } else { Vec::new() };
    let other = OTHER_VALUES.iter().find(|(name, _)| *name == long).map(|(_, d)| *d);
    let range = match (&number, choices.is_empty(), other) {
        (Some(n), _, Some(more)) => format!("{}, {more}", n.describe()),
        (Some(n), _, None) => n.describe(),
        (None, false, _) => format!("one of {}", choices.join(", ")),
        (None, true, Some(d)) => d.to_string(),
        (None, true, None) => String::new(),
    };
    let default = arg.get_default_values().iter().map(|v| v.to_string_lossy().into_owned()).collect::<Vec<_>>();
    let help =
        arg.get_help().map(|h| h.to_string().split_whitespace().collect::<Vec<_>>().join(" ")).unwrap_or_default();
    Some(OptionRow {
        command: command.into(),
        option: format!("--{long}"),
        value: if takes && value.is_empty() { long.to_uppercase() } else { value },
        range,
        default: default.join(", "),
        help,
        number,
        choices,
    })
}

/// `docs/options.md`: the table of every option, one section per command.
pub fn markdown(cli: &clap::Command) -> String {
    let cell = |s: &str| if s.is_empty() { "—".to_string() } else { s.replace('|', "\\|") };
    let mut out = String::from(
        "# Every option of `vcuts`, with its range\n\n\
         Generated from the command line's definition by `cargo xtask publish` (CI checks it is \
         current): do not edit. A number outside its range, a choice not listed, or a value that \
         does not parse is refused as the command line is read, naming the option.\n",
    );
    let mut current = None;
    for r in table(cli) {
        if current.as_ref() != Some(&r.command) {
            let title =
                if r.command.is_empty() { "Every command".to_string() } else { format!("`vcuts {}`", r.command) };
            out.push_str(&format!(
                "\n## {title}\n\n| option | value | range | default | what |\n|---|---|---|---|---|\n"
            ));
            current = Some(r.command.clone());
        }
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} |\n",
            r.option,
            cell(&r.value),
            cell(&r.range),
            cell(&r.default),
            cell(&r.help)
        ));
    }
    out
}
