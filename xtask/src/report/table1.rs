//! The paper's Table 1 beside ours: the bench report's scenes as Markdown (spliced into the
//! README by `cargo xtask publish`) and CSV rows.

use crate::report::SceneFigures;
use std::collections::BTreeMap;

/// A row of the paper's Table 1 (Core2 Quad Q9650 + GTX 280).
struct PaperRow {
    scene: &'static str,
    vertices: u32,
    objects: u32,
    baseline_mb: f64,
    baseline_edit_s: f64,
    baseline_move_s: f64,
    mb: f64,
    edit_s: f64,
    move_s: f64,
}

const PAPER: [PaperRow; 2] = [
    PaperRow {
        scene: "teapot",
        vertices: 11_565,
        objects: 3,
        baseline_mb: 266.0,
        baseline_edit_s: 0.13,
        baseline_move_s: 2.03,
        mb: 97.0,
        edit_s: 0.13,
        move_s: 1.79,
    },
    PaperRow {
        scene: "bunny",
        vertices: 40_172,
        objects: 2,
        baseline_mb: 251.0,
        baseline_edit_s: 0.50,
        baseline_move_s: 3.41,
        mb: 117.0,
        edit_s: 0.50,
        move_s: 3.36,
    },
];

/// Table 1 as Markdown and CSV rows.
pub fn table1(scenes: &BTreeMap<String, SceneFigures>) -> (String, String) {
    let mut md = String::from(
        "| scene | preset | vertices | objects | data MB (ours / index baseline) | edit ms (ours / index) | move ms (ours / index) | paper: data MB (paper / baseline) | paper: edit s (paper / baseline) | paper: move s (paper / baseline) |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let mut csv = String::from(
        "scene,preset,vertices,objects,data_mb,data_mb_index,edit_ms,edit_ms_index,move_ms,move_ms_index,paper_vertices,paper_objects,paper_data_mb,paper_data_mb_baseline,paper_edit_s,paper_move_s,paper_move_s_baseline\n",
    );
    for (name, s) in scenes {
        let p = PAPER.iter().find(|p| p.scene == name);
        let (preset, vertices, objects) = (&s.preset, s.vertices, s.objects);
        let [data, data_index, edit, edit_index, mv, mv_index] = [
            s.precompute.data_bytes_height as f64 / 1e6,
            s.precompute.data_bytes_index as f64 / 1e6,
            s.edit_ms,
            s.edit_ms_index,
            s.move_ms,
            s.move_ms_index,
        ];
        md.push_str(&format!(
            "| {name} | {preset} | {vertices} | {objects} | {data:.1} / {data_index:.1} | {edit:.1} / {edit_index:.1} | {mv:.0} / {mv_index:.0} | {} | {} | {} |\n",
            p.map(|p| format!("{} / {}", p.mb, p.baseline_mb)).unwrap_or_default(),
            p.map(|p| format!("{} / {}", p.edit_s, p.baseline_edit_s)).unwrap_or_default(),
            p.map(|p| format!("{} / {}", p.move_s, p.baseline_move_s)).unwrap_or_default(),
        ));
        let paper = p.map_or_else(
            || ",,,,,,".into(),
            |p| {
                format!(
                    "{},{},{},{},{},{},{}",
                    p.vertices, p.objects, p.mb, p.baseline_mb, p.edit_s, p.move_s, p.baseline_move_s
                )
            },
        );
        csv.push_str(&format!(
            "{name},{preset},{vertices},{objects},{data:.3},{data_index:.3},{edit:.3},{edit_index:.3},{mv:.3},{mv_index:.3},{paper}\n"
        ));
    }
    (md, csv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::PrecomputeFigures;

    #[test]
    fn table1_puts_the_papers_figures_beside_ours() {
        let mut scenes = BTreeMap::new();
        let precompute = PrecomputeFigures {
            data_bytes_height: 56_000_000,
            data_bytes_index: 560_000_000,
            ..PrecomputeFigures::default()
        };
        scenes.insert(
            "teapot".to_string(),
            SceneFigures {
                preset: "paper".into(),
                vertices: 11564,
                objects: 3,
                edit_ms: 30.0,
                edit_ms_index: 31.0,
                move_ms: 400.0,
                move_ms_index: 900.0,
                precompute,
                ..SceneFigures::default()
            },
        );
        let (md, csv) = table1(&scenes);
        let row = md.lines().nth(2).unwrap();
        assert!(
            row.contains("| teapot | paper | 11564 | 3 | 56.0 / 560.0 | 30.0 / 31.0 | 400 / 900 | 97 / 266 |"),
            "{row}"
        );
        assert!(row.contains("1.79 / 2.03"), "{row}");
        let fields: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
        assert_eq!(fields.len(), csv.lines().next().unwrap().split(',').count());
        assert_eq!(fields[0], "teapot");
    }
}
