//! The sweep's results as a terminal table shaped like Bikker's appendix D (one row per
//! technique, one column per sample count, each cell ms / RMSE / Mrays/s), CSV and JSON.

use std::fmt::Write as _;

use super::{Report, Row};

/// The techniques and sample counts of `rows`, in the order they first appear.
fn axes(rows: &[Row]) -> (Vec<&str>, Vec<u32>) {
    let (mut techniques, mut spps): (Vec<&str>, Vec<u32>) = (Vec::new(), Vec::new());
    for r in rows {
        if !techniques.contains(&r.technique.as_str()) {
            techniques.push(&r.technique);
        }
        if !spps.contains(&r.spp) {
            spps.push(r.spp);
        }
    }
    (techniques, spps)
}

pub fn table(rows: &[Row]) -> String {
    let (techniques, spps) = axes(rows);
    let mut s = format!("{:<18}", "ms / RMSE / Mrays");
    for spp in &spps {
        let _ = write!(s, " {:>24}", format!("{spp} spp"));
    }
    s.push('\n');
    for t in &techniques {
        let biased = rows.iter().any(|r| r.technique == *t && r.biased);
        let _ = write!(
            s,
            "{:<18}",
            if biased {
                format!("{t} *")
            } else {
                t.to_string()
            }
        );
        for spp in &spps {
            match rows.iter().find(|r| r.technique == *t && r.spp == *spp) {
                Some(r) => {
                    let cell = format!("{:.1} / {:.4} / {:.1}", r.ms, r.rmse, r.mrays);
                    let _ = write!(s, " {cell:>24}");
                }
                None => {
                    let _ = write!(s, " {:>24}", "-");
                }
            }
        }
        s.push('\n');
    }
    if rows.iter().any(|r| r.biased) {
        s.push_str("* biased: converges to something else than the reference\n");
    }
    s
}

/// The columns of a report row, in the CSV and as the JSON rows' keys.
pub const COLUMNS: [&str; 9] = [
    "technique",
    "spp",
    "ms",
    "rmse",
    "relmse",
    "flip",
    "mrays",
    "efficiency",
    "biased",
];

pub fn csv(rows: &[Row]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let _ = w.write_record(COLUMNS);
    for r in rows {
        let _ = w.write_record([
            r.technique.clone(),
            r.spp.to_string(),
            format!("{:.3}", r.ms),
            format!("{:.6e}", r.rmse),
            format!("{:.6e}", r.relmse),
            format!("{:.5}", r.flip),
            format!("{:.3}", r.mrays),
            format!("{:.6e}", r.efficiency),
            r.biased.to_string(),
        ]);
    }
    String::from_utf8(w.into_inner().unwrap_or_default()).unwrap_or_default()
}

pub fn json(report: &Report) -> String {
    let rows: Vec<serde_json::Value> = report
        .rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "technique": r.technique,
                "spp": r.spp,
                "ms": r.ms,
                "rmse": r.rmse,
                "relmse": r.relmse,
                "flip": r.flip,
                "mrays": r.mrays,
                "efficiency": r.efficiency,
                "biased": r.biased,
            })
        })
        .collect();
    serde_json::json!({
        "reference": report.reference.display().to_string(),
        "reference_spp": report.reference_spp,
        "rows": rows,
    })
    .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(t: &str, spp: u32, biased: bool) -> Row {
        Row {
            technique: t.into(),
            spp,
            ms: 1.5,
            rmse: 0.25,
            relmse: 0.5,
            flip: 0.1,
            mrays: 10.0,
            efficiency: 10.0,
            biased,
        }
    }

    #[test]
    fn the_table_has_a_row_per_technique_and_a_column_per_spp() {
        let rows = vec![
            row("mis", 4, false),
            row("mis", 16, false),
            row("max-depth=2", 4, true),
        ];
        let t = table(&rows);
        let lines: Vec<&str> = t.lines().collect();
        assert!(lines[0].contains("4 spp") && lines[0].contains("16 spp"));
        assert!(lines[1].starts_with("mis") && lines[1].contains("1.5 / 0.2500 / 10.0"));
        assert!(lines[2].starts_with("max-depth=2 *") && lines[2].trim_end().ends_with('-'));
        assert!(t.contains("* biased"));
        assert_eq!(csv(&rows).lines().count(), 4);
    }
}
