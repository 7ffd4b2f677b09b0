//! The time-local section of the diagnosis report: the events the scan found and the
//! detectable size of a step through each run.

use sins_config::markdown::Table;
use sins_diag::events::EventScan;
use std::fmt::Write as _;

/// The events table and a detectable-step table (levels at the onsets listed, per channel).
pub fn render_events(scan: &EventScan) -> String {
    let mut md = String::from("\n### Effects local in time\n\n");
    if scan.tests == 0 {
        md.push_str("The scan for steps, ramps, transients, pulses and plateaus was off.\n");
        return md;
    }
    let _ = writeln!(
        md,
        "A likelihood-ratio scan over onset time for bias steps, ramps, exponential \
         transients, pulses and ramps to a plateau on each sensor axis of each run, against the winner's fit (or the twin): \
         {} tests, Bonferroni threshold χ² = {:.1}. An event no catalogue term explains is an \
         effect outside the catalogue. Onset ± 1σ from the profile likelihood (3σ interval: the \
         onsets within Δχ² = 9 of the best). \"not told from\" lists the other channels whose best \
         signal comes within Δχ² = 9 of the event's: the data do not say which of them it is.\n",
        scan.tests, scan.threshold_chi2
    );
    if scan.events.is_empty() {
        md.push_str("No event.\n");
    } else {
        let mut t = Table::new([
            "run",
            "channel",
            "shape",
            "onset ± 1σ (s)",
            "size ± 1σ",
            "τ or duration (s)",
            "χ²",
            "p",
            "explained by",
            "not told from",
        ]);
        for e in &scan.events {
            t.row([
                e.run.clone(),
                e.channel.clone(),
                e.shape.clone(),
                format!("{:.0} ± {:.0}", e.onset_s, e.onset_sigma_s),
                format!("{:.3e} ± {:.1e} {}", e.size, e.size_sigma, e.unit),
                e.time_constant_s
                    .or(e.duration_s)
                    .map_or("-".into(), |t| format!("{t:.0}")),
                format!("{:.1}", e.chi2),
                format!("{:.1e}", e.p_value),
                e.explained_by
                    .as_deref()
                    .unwrap_or("outside the catalogue")
                    .to_string(),
                if e.alternatives.is_empty() {
                    "-".to_string()
                } else {
                    e.alternatives
                        .iter()
                        .map(|a| format!("{} (χ² {:.1})", a.channel, a.chi2))
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            ]);
        }
        md.push_str(&t.render());
    }
    let mut runs: Vec<&str> = scan.detectable.iter().map(|c| c.run.as_str()).collect();
    runs.dedup();
    for run in runs {
        let steps: Vec<_> = scan
            .detectable
            .iter()
            .filter(|c| c.run == run && c.shape == "step")
            .collect();
        let Some(first) = steps.first() else { continue };
        let mut t = Table::new(
            std::iter::once("channel".to_string())
                .chain(first.onset_s.iter().map(|t| format!("{:.1}", t / 3600.0))),
        );
        for c in &steps {
            t.row(
                std::iter::once(format!("{} ({})", c.channel, c.unit))
                    .chain(c.level.iter().map(|v| format!("{v:.2e}"))),
            );
        }
        let _ = write!(
            md,
            "\nDetectable step in {run} (90 % power at the scan's level) by onset time (h):\n\n{t}"
        );
        let turn_on: Vec<_> = scan
            .detectable
            .iter()
            .filter(|c| c.run == run && c.shape == "turn-on transient")
            .collect();
        // One column per time constant: the rows come channel by channel, each with every one.
        let mut taus: Vec<f64> = turn_on.iter().filter_map(|c| c.time_constant_s).collect();
        taus.sort_by(f64::total_cmp);
        taus.dedup();
        if taus.is_empty() {
            continue;
        }
        let mut t = Table::new(
            std::iter::once("channel".to_string()).chain(taus.iter().map(|t| format!("{t:.0}"))),
        );
        for s in &steps {
            let cells = taus.iter().map(|t| {
                turn_on
                    .iter()
                    .find(|c| c.channel == s.channel && c.time_constant_s == Some(*t))
                    .and_then(|c| c.level.first())
                    .map_or("-".into(), |v| format!("{v:.2e}"))
            });
            t.row(std::iter::once(format!("{} ({})", s.channel, s.unit)).chain(cells));
        }
        let _ = write!(
            md,
            "\nDetectable turn-on transient in {run} (its value at turn-on) by time constant (s):\n\n{t}"
        );
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_diag::events::DetectableCurve;

    fn curve(channel: &str, shape: &str, tau: Option<f64>, level: f64) -> DetectableCurve {
        DetectableCurve {
            run: "nav1".into(),
            channel: channel.into(),
            shape: shape.into(),
            time_constant_s: tau,
            duration_s: None,
            unit: "deg/h".into(),
            onset_s: vec![1080.0, 4680.0],
            level: vec![level, level],
        }
    }

    #[test]
    fn the_turn_on_table_has_one_column_per_time_constant() {
        // Curves come channel by channel, each with every time constant (as the scan lists
        // them): the columns must not repeat once per channel.
        let mut detectable = Vec::new();
        for (k, ch) in ["gyro x", "gyro y"].iter().enumerate() {
            detectable.push(curve(ch, "step", None, 1e-3));
            for (j, tau) in [300.0, 600.0, 1200.0].iter().enumerate() {
                let level = (10 * k + j) as f64;
                detectable.push(curve(ch, "turn-on transient", Some(*tau), level));
            }
        }
        let scan = EventScan {
            tests: 1,
            threshold_chi2: 30.0,
            detectable,
            ..EventScan::default()
        };
        let md = render_events(&scan);
        let table = md
            .split("Detectable turn-on transient in nav1")
            .nth(1)
            .expect("a turn-on table");
        let lines: Vec<&str> = table.lines().filter(|l| l.starts_with('|')).collect();
        assert_eq!(lines[0], "| channel | 300 | 600 | 1200 |", "{table}");
        // Each cell is its own channel's level at that time constant.
        assert_eq!(lines[2], "| gyro x (deg/h) | 0.00e0 | 1.00e0 | 2.00e0 |");
        assert_eq!(lines[3], "| gyro y (deg/h) | 1.00e1 | 1.10e1 | 1.20e1 |");
    }
}
