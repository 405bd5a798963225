//! `cargo xtask publish`: a bench report's generated tables into the docs. Copies
//! `table1.md` (and the trade-off plot, when there is one) from the report folder to
//! `docs/report/`, and writes the table between the `<!-- table1 -->` and `<!-- /table1 -->`
//! markers of `README.md` and `docs/benchmarks.md`, so the tables there are always a command's
//! output, never edited by hand.

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

const BEGIN: &str = "<!-- table1 -->";
const END: &str = "<!-- /table1 -->";
const DOCS: [&str; 2] = ["README.md", "docs/benchmarks.md"];

/// `text` with the block between the markers replaced by `table`; `None` without markers.
pub fn splice(text: &str, table: &str) -> Option<String> {
    let a = text.find(BEGIN)? + BEGIN.len();
    let b = a + text[a..].find(END)?;
    Some(format!("{}\n{}\n{}", &text[..a], table.trim_end(), &text[b..]))
}

/// Runs `publish`.
pub fn run(args: &PublishArgs) -> Result<()> {
    let kept = Path::new("docs/report");
    let report = args.report.as_deref().unwrap_or(kept);
    let source = report.join("table1.md");
    let table = std::fs::read_to_string(&source).with_context(|| format!("reading {}", source.display()))?;
    if !table.trim_start().starts_with("| scene |") {
        bail!("{}: not a Table 1 written by `cargo xtask bench`", source.display());
    }
    let mut stale = Vec::new();
    for doc in DOCS {
        let text = std::fs::read_to_string(doc).with_context(|| format!("reading {doc}"))?;
        let new = splice(&text, &table).with_context(|| format!("{doc}: no {BEGIN} … {END} markers"))?;
        if new != text {
            stale.push(doc);
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
        for name in ["table1.md", "tradeoff_size.png"] {
            let from = report.join(name);
            if from.exists() {
                std::fs::copy(&from, kept.join(name)).with_context(|| format!("copying {}", from.display()))?;
            }
        }
    }
    for doc in DOCS {
        println!("{doc}: {}", if stale.contains(&doc) { "table written" } else { "already current" });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splice_replaces_only_between_the_markers() {
        let text = "a\n<!-- table1 -->\nold\n<!-- /table1 -->\nb\n";
        assert_eq!(splice(text, "| scene |\n").unwrap(), "a\n<!-- table1 -->\n| scene |\n<!-- /table1 -->\nb\n");
        assert_eq!(splice(&splice(text, "| x |").unwrap(), "| x |").unwrap(), splice(text, "| x |").unwrap());
        assert!(splice("no markers", "t").is_none());
    }
}
