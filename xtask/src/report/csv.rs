//! The bench's CSV tables: the trade-off sweeps' points (written, and read back to re-plot
//! them) and the scaling section's points. One row a point, one column a figure.

use crate::measure::scaling::ScalingPoint;
use crate::report::Point;
use anyhow::{Context, Result};

/// The figures of a point, in CSV column order.
const KEYS: [&str; 8] =
    ["directions", "precompute_s", "data_bytes", "merge_ms", "shade_ms", "move_ms", "rel_l2_exact", "rel_l2_mc"];

/// The points as CSV.
pub fn tradeoff(points: &[Point]) -> String {
    let keys = KEYS;
    let mut out = format!("sweep,value,preset,{},pareto_size,pareto_move\n", keys.join(","));
    for p in points {
        let figs: Vec<String> = keys.iter().map(|k| format!("{}", p.figures[k])).collect();
        out.push_str(&format!(
            "{},{},{},{},{},{}\n",
            p.sweep,
            p.value,
            p.preset,
            figs.join(","),
            u8::from(p.pareto_size),
            u8::from(p.pareto_move)
        ));
    }
    out
}

/// Reads what [`tradeoff`] wrote (to re-plot without re-running the sweeps).
pub fn parse_tradeoff(text: &str) -> Result<Vec<Point>> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().context("empty trade-off CSV")?.split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).with_context(|| format!("no column {name}"));
    let (sweep, value, preset) = (col("sweep")?, col("value")?, col("preset")?);
    let (ps, pm) = (col("pareto_size")?, col("pareto_move")?);
    let figure_cols: Vec<(&'static str, usize)> =
        KEYS.iter().map(|&k| col(k).map(|c| (k, c))).collect::<Result<_>>()?;
    lines
        .enumerate()
        .map(|(i, line)| {
            let f: Vec<&str> = line.split(',').collect();
            anyhow::ensure!(f.len() == header.len(), "line {}: {} fields, expected {}", i + 2, f.len(), header.len());
            let figures = figure_cols
                .iter()
                .map(|&(k, c)| Ok((k, f[c].parse::<f64>().with_context(|| format!("line {}: {k} = {}", i + 2, f[c]))?)))
                .collect::<Result<_>>()?;
            Ok(Point {
                sweep: f[sweep].into(),
                value: f[value].into(),
                preset: f[preset].into(),
                figures,
                pareto_size: f[ps] == "1",
                pareto_move: f[pm] == "1",
            })
        })
        .collect()
}

/// Every point as a CSV row.
pub fn scaling(points: &[ScalingPoint]) -> String {
    let mut text = String::from("sweep,preset,objects,movable,vertices");
    for key in crate::measure::scaling::FITTED {
        text.push(',');
        text.push_str(key);
    }
    text.push_str(",merged_vertices_eager,nodes_per_merged_vertex,ns_per_merged_node,rel_l2_exact\n");
    for p in points {
        text.push_str(&format!("{},{},{},{},{}", p.sweep, p.preset, p.objects, p.movable, p.vertices));
        for key in crate::measure::scaling::FITTED {
            text.push_str(&format!(",{}", p.figure(key)));
        }
        text.push_str(&format!(
            ",{},{},{},{}\n",
            p.merged_vertices_eager, p.nodes_per_merged_vertex, p.ns_per_merged_node, p.rel_l2_exact
        ));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_rows_carry_every_figure_and_the_fronts() {
        let figures = KEYS.into_iter().enumerate().map(|(i, k)| (k, i as f64)).collect();
        let p = Point {
            sweep: "directions".into(),
            value: "4096".into(),
            preset: "fast".into(),
            figures,
            pareto_size: true,
            pareto_move: false,
        };
        let text = tradeoff(std::slice::from_ref(&p));
        let back = parse_tradeoff(&text).unwrap();
        assert_eq!((back[0].figures.clone(), back[0].pareto_size), (p.figures.clone(), true));
        assert!(parse_tradeoff("sweep,value\n").unwrap_err().to_string().contains("no column"));
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(header.len(), row.len());
        assert_eq!(row[header.iter().position(|h| *h == "rel_l2_exact").unwrap()], "6");
        assert_eq!(&row[row.len() - 2..], ["1", "0"]);
        let json = serde_json::to_value(&p).unwrap();
        assert_eq!(
            (&json["move_ms"], &json["sweep"], &json["pareto_size"]),
            (&5.0.into(), &p.sweep.clone().into(), &true.into())
        );
    }

    #[test]
    fn scaling_rows_carry_every_fitted_figure() {
        let p = ScalingPoint {
            sweep: "objects".into(),
            preset: "fast".into(),
            objects: 5,
            movable: 4,
            vertices: 2_000,
            move_ms_eager: 12.5,
            merged_vertices_eager: 900,
            rel_l2_exact: 0.01,
            ..ScalingPoint::default()
        };
        let text = scaling(&[p.clone(), p]);
        let lines: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
        assert_eq!(lines.len(), 3);
        assert!(lines.iter().all(|l| l.len() == lines[0].len()));
        let col = |name: &str| lines[0].iter().position(|h| *h == name).unwrap();
        assert_eq!((lines[1][col("move_ms_eager")], lines[1][col("movable")]), ("12.5", "4"));
        assert_eq!(lines[2][col("merged_vertices_eager")], "900");
        assert_eq!(crate::measure::scaling::FITTED.len() + 9, lines[0].len());
    }
}
