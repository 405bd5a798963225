//! `cargo xtask publish`: what the docs show, generated. Copies a bench report's `table1.md`
//! and plots (trade-off, scaling, accuracy, assembly, turns: those it has; a report of one section, e.g. from
//! `bench --only scaling`, brings its plots and keeps the table there) to `docs/report/` and
//! writes the table between the `<!-- table1 -->` and `<!-- /table1 -->` markers of
//! `README.md` and `docs/benchmarks.md`; and writes each library crate's `README.md` (what a registry page
//! shows) from its crate documentation, and `docs/options.md` (every option of `vcuts` with its
//! range) from the command line's definition — so none of them is edited by hand. It also requires
//! every library crate to carry a version of its own and a `CHANGELOG.md` entry for it.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// Arguments of `publish`.
#[derive(clap::Args)]
pub struct PublishArgs {
    /// The report folder (from `cargo xtask bench --out`); default: `docs/report` itself, which
    /// only rewrites the docs' tables from the table kept there.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Only check that the docs hold the report's table (exit 1 if not), changing nothing.
    #[arg(long)]
    pub check: bool,
}

/// The markers of Table 1's block.
const TABLE1: (&str, &str) = ("<!-- table1 -->", "<!-- /table1 -->");
/// The markers of the accuracy section's worst cases (README only).
const WORST: (&str, &str) = ("<!-- accuracy-worst -->", "<!-- /accuracy-worst -->");
const DOCS: [&str; 2] = ["README.md", "docs/benchmarks.md"];
/// What a report brings to `docs/report/`, those it has.
const PUBLISHED: [&str; 9] = [
    "table1.md",
    "tradeoff_size.png",
    "scaling_objects.png",
    "scaling_vertices.png",
    "accuracy.md",
    "accuracy.png",
    "assembly.md",
    "assembly.png",
    "turns.md",
];

/// `text` with the block between the markers replaced by `table`; `None` without markers.
pub fn splice(text: &str, (begin, end): (&str, &str), table: &str) -> Option<String> {
    let a = text.find(begin)? + begin.len();
    let b = a + text[a..].find(end)?;
    Some(format!("{}\n{}\n{}", &text[..a], table.trim_end(), &text[b..]))
}

/// The README's worst-case lines from an `accuracy.md`: its `Worst at` lines, one per preset,
/// as a list; `None` when it has none (not a table `bench` wrote).
pub fn worst_cases(accuracy_md: &str) -> Option<String> {
    let lines: Vec<String> =
        accuracy_md.lines().filter(|l| l.starts_with("Worst at ")).map(|l| format!("- {l}")).collect();
    (!lines.is_empty()).then(|| lines.join("\n"))
}

/// Runs `publish`.
pub fn run(args: &PublishArgs) -> Result<()> {
    let kept = Path::new("docs/report");
    let report = args.report.as_deref().unwrap_or(kept);
    // A report without a table (one section measured) keeps the table published before.
    let source = Some(report.join("table1.md")).filter(|s| s.exists()).unwrap_or_else(|| kept.join("table1.md"));
    let table = std::fs::read_to_string(&source).with_context(|| format!("reading {}", source.display()))?;
    if !table.trim_start().starts_with("| scene |") {
        bail!("{}: not a Table 1 written by `cargo xtask bench`", source.display());
    }
    // The accuracy section's worst cases: the report's `accuracy.md`, else the one published.
    let accuracy = Some(report.join("accuracy.md")).filter(|s| s.exists()).unwrap_or_else(|| kept.join("accuracy.md"));
    let worst = match std::fs::read_to_string(&accuracy) {
        Ok(md) => Some(worst_cases(&md).with_context(|| format!("{}: no `Worst at` lines", accuracy.display()))?),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(e).with_context(|| format!("reading {}", accuracy.display())),
    };
    let mut stale: Vec<String> = crate_readmes(args.check)?;
    stale.extend(options_table(args.check)?);
    for doc in DOCS {
        let text = std::fs::read_to_string(doc).with_context(|| format!("reading {doc}"))?;
        let mut new =
            splice(&text, TABLE1, &table).with_context(|| format!("{doc}: no {} … {} markers", TABLE1.0, TABLE1.1))?;
        if let (Some(worst), true) = (&worst, doc == "README.md") {
            new = splice(&new, WORST, worst).with_context(|| format!("{doc}: no {} … {} markers", WORST.0, WORST.1))?;
        }
        if new != text {
            stale.push(doc.to_string());
            if !args.check {
                std::fs::write(doc, new).with_context(|| format!("writing {doc}"))?;
            }
        }
    }
    if args.check {
        if !stale.is_empty() {
            bail!("{} not the table of {} (run `cargo xtask publish`)", stale.join(" and "), source.display());
        }
        println!("docs hold {}", source.display());
        return Ok(());
    }
    if report != kept {
        std::fs::create_dir_all(kept).with_context(|| format!("creating {}", kept.display()))?;
        for name in PUBLISHED {
            let from = report.join(name);
            if from.exists() {
                std::fs::copy(&from, kept.join(name)).with_context(|| format!("copying {}", from.display()))?;
            }
        }
    }
    for doc in DOCS {
        println!("{doc}: {}", if stale.iter().any(|s| s == doc) { "table written" } else { "already current" });
    }
    for s in stale.iter().filter(|s| s.ends_with("/README.md")) {
        println!("{s}: written from the crate documentation");
    }
    if stale.iter().any(|s| s == OPTIONS) {
        println!("{OPTIONS}: written from the command line's definition");
    }
    Ok(())
}

/// Where the table of every command-line option goes.
const OPTIONS: &str = "docs/options.md";

/// Writes (or with `check` only compares) `docs/options.md`, the table of every option of
/// `vcuts` with its range (`vcuts::options::markdown`); returns it when it was stale.
fn options_table(check: bool) -> Result<Option<String>> {
    use clap::CommandFactory;
    let md = vcuts::options::markdown(&vcuts::Cli::command());
    if std::fs::read_to_string(OPTIONS).ok().as_deref() == Some(md.as_str()) {
        return Ok(None);
    }
    if !check {
        std::fs::write(OPTIONS, &md).with_context(|| format!("writing {OPTIONS}"))?;
    }
    Ok(Some(OPTIONS.to_string()))
}

/// A crate's `README.md`: its name, its description, and its crate documentation (the `//!`
/// lines of `src/lib.rs`) with rustdoc's links made plain code and its examples Rust blocks.
pub fn crate_readme(name: &str, description: &str, lib_rs: &str) -> String {
    let mut out = format!("# {name}\n\n{description}\n\n");
    let mut in_code = false;
    for line in lib_rs.lines().take_while(|l| l.starts_with("//!") || l.trim().is_empty()) {
        let Some(text) = line.strip_prefix("//!") else { continue };
        let text = text.strip_prefix(' ').unwrap_or(text);
        if let Some(fence) = text.strip_prefix("```") {
            in_code = !in_code;
            out.push_str(if in_code && !fence.contains("text") { "```rust" } else { "```" });
        } else if in_code {
            out.push_str(text);
        } else {
            // [`x`] and [`x`](path) links to items resolve on docs.rs, not here; the docs'
            // headings sit one level below the README's title.
            let mut t = if text.starts_with('#') { format!("#{text}") } else { text.to_string() };
            while let Some(a) = t.find("[`") {
                let Some(b) = t[a..].find("`]").map(|b| a + b) else { break };
                let mut end = b + 2;
                if t[end..].starts_with('(') {
                    end = t[end..].find(')').map_or(end, |c| end + c + 1);
                }
                t = format!("{}`{}`{}", &t[..a], &t[a + 2..b], &t[end..]);
            }
            out.push_str(&t);
        }
        out.push('\n');
    }
    out.push_str("\nPart of the vcuts workspace: see its README and ARCHITECTURE.md.\n");
    out
}

/// Writes (or with `check`, only compares) every library crate's README; returns the stale ones.
fn crate_readmes(check: bool) -> Result<Vec<String>> {
    let mut stale = Vec::new();
    let mut dirs: Vec<PathBuf> = std::fs::read_dir("crates")
        .context("reading crates/")?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.join("src/lib.rs").exists())
        .collect();
    dirs.sort();
    for dir in dirs {
        let manifest = std::fs::read_to_string(dir.join("Cargo.toml"))
            .with_context(|| format!("reading {}", dir.join("Cargo.toml").display()))?;
        let field = |key: &str| {
            manifest.lines().find_map(|l| {
                let (k, v) = l.split_once('=')?;
                (k.trim() == key).then(|| v.trim().trim_matches('"').replace("\\\"", "\""))
            })
        };
        let name = field("name").with_context(|| format!("{}: no package name", dir.display()))?;
        let version = field("version").with_context(|| {
            format!("{}: no version of its own (each library crate is versioned alone)", dir.display())
        })?;
        let changelog = dir.join("CHANGELOG.md");
        let log = std::fs::read_to_string(&changelog).with_context(|| format!("reading {}", changelog.display()))?;
        if !has_entry(&log, &version) {
            bail!("{}: no `## {version}` entry for the version in {}/Cargo.toml", changelog.display(), dir.display());
        }
        let description = field("description").unwrap_or_default();
        let lib = std::fs::read_to_string(dir.join("src/lib.rs"))?;
        let readme = crate_readme(&name, &description, &lib);
        let path = dir.join("README.md");
        if std::fs::read_to_string(&path).ok().as_deref() != Some(readme.as_str()) {
            stale.push(path.display().to_string());
            if !check {
                std::fs::write(&path, readme).with_context(|| format!("writing {}", path.display()))?;
            }
        }
    }
    Ok(stale)
}

/// Whether `changelog` has a `## VERSION` heading (followed by the end of the line or a space).
fn has_entry(changelog: &str, version: &str) -> bool {
    changelog.lines().any(|l| {
        l.strip_prefix("## ").and_then(|r| r.strip_prefix(version)).is_some_and(|r| r.is_empty() || r.starts_with(' '))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splice_replaces_only_between_the_markers() {
        let text = "a\n<!-- table1 -->\nold\n<!-- /table1 -->\nb\n";
        assert_eq!(
            splice(text, TABLE1, "| scene |\n").unwrap(),
            "a\n<!-- table1 -->\n| scene |\n<!-- /table1 -->\nb\n"
        );
        let once = splice(text, TABLE1, "| x |").unwrap();
        assert_eq!(splice(&once, TABLE1, "| x |").unwrap(), once);
        assert!(splice("no markers", TABLE1, "t").is_none());
        assert!(splice(text, WORST, "t").is_none());
    }

    #[test]
    fn the_worst_cases_are_the_accuracy_tables_worst_lines() {
        let md = "| scene |\n|---|\n| teapot |\n\nWorst at `fast`: teapot under x (rest), 4.00 % against the exact reference.\n\nWorst at `paper`: bunny under y (moved), 0.40 % against the exact reference.\n\nSkipped: z\n";
        assert_eq!(
            worst_cases(md).unwrap(),
            "- Worst at `fast`: teapot under x (rest), 4.00 % against the exact reference.\n- Worst at `paper`: bunny under y (moved), 0.40 % against the exact reference."
        );
        assert!(worst_cases("| scene |\n").is_none());
    }

    #[test]
    fn a_changelog_entry_names_the_exact_version() {
        let log = "# Changelog\n\n## 0.2.0 — unreleased\n\n## 0.1.0\n";
        assert!(has_entry(log, "0.2.0") && has_entry(log, "0.1.0"));
        assert!(!has_entry(log, "0.1") && !has_entry(log, "0.2.1") && !has_entry("0.1.0", "0.1.0"));
    }

    #[test]
    fn a_crate_readme_is_its_crate_docs_made_plain() {
        let lib = "//! Cuts, see [`Cut`] and [`merge`](crate::merge).\n//!\n//! # Example\n//! ```no_run\n//! let x = 1;\n//! ```\n\nuse x;\n//! not docs\n";
        let r = crate_readme("vcut-x", "What it is.", lib);
        let want = "# vcut-x\n\nWhat it is.\n\nCuts, see `Cut` and `merge`.\n\n## Example\n```rust\nlet x = 1;\n```\n";
        assert!(r.starts_with(want), "{r}");
        assert!(!r.contains("not docs"));
    }
}
