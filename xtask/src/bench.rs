//! `cargo xtask bench [--write] [--only NAME]`: rerun the main benchmarks and print today's
//! figures as one table (`--write`: also into BENCHMARKS.md, between its dashboard markers).
//!
//! Each benchmark prints its own detailed table; this runs them in turn, picks out the figure
//! each dashboard row reports (a criterion median, or a cell of a row the bench prints), and
//! fails naming the row when a bench no longer prints it, so the dashboard cannot go stale
//! silently.
use std::path::Path;
use std::process::{Command, ExitCode};

/// How a row's figure is found in its bench's output.
enum Find {
    /// A criterion benchmark by its id: the middle of its `time: [lo mid hi]` estimate.
    Criterion(&'static str),
    /// The first line containing the text: the listed cells of that `| a | b |` row (counted
    /// from 0, the label being 0), joined with ", ".
    Cells(&'static str, &'static [usize]),
    /// The first line containing the text, as printed.
    Line(&'static str),
}

/// One row of the dashboard.
struct Row {
    what: &'static str,
    find: Find,
    goal: &'static str,
}

/// One bench run and the rows it gives.
struct Run {
    name: &'static str,
    /// The arguments of `cargo` (and the environment it needs), as the dashboard prints them.
    cargo: &'static [&'static str],
    env: &'static [(&'static str, &'static str)],
    rows: &'static [Row],
}

const CRITERION_QUICK: &str = "--warm-up-time 1 --measurement-time 5 --noplot";

const RUNS: &[Run] = &[
    Run {
        name: "firmware",
        cargo: &["bench", "-p", "card-emu", "--bench", "firmware", "--", "--warm-up-time", "1", "--measurement-time", "5", "--noplot"],
        env: &[],
        rows: &[
            Row {
                what: "firmware tick, 8 axes moving + plant",
                find: Find::Criterion("firmware tick, 8 moving axes + plant"),
                goal: "≤ 1.0 µs",
            },
            Row {
                what: "firmware tick, a 3-axis group line + 5 axes moving + plant",
                find: Find::Criterion("firmware tick, 3-axis group line + 5 moving axes + plant"),
                goal: "",
            },
            Row {
                what: "a new lease of the emulator's window",
                find: Find::Criterion("a new lease: window copied and remapped, new eventfd"),
                goal: "",
            },
        ],
    },
    Run {
        name: "roundtrip",
        cargo: &["bench", "-p", "card-emu", "--bench", "roundtrip"],
        env: &[],
        rows: &[
            Row {
                what: "command round trip to a card-emu process, busy-poll: n, p50, p99, p99.9, max µs",
                find: Find::Cells("round trip, emulator busy-poll", &[1, 2, 3, 4, 5]),
                goal: "",
            },
            Row {
                what: "the same, the card sleeping between ticks",
                find: Find::Cells("round trip, emulator sleeping", &[1, 2, 3, 4, 5]),
                goal: "",
            },
            Row {
                what: "commands a second to a card-emu process, busy-poll",
                find: Find::Cells("commands/s, emulator busy-poll", &[2]),
                goal: "",
            },
        ],
    },
    Run {
        name: "otg",
        cargo: &["bench", "-p", "card-emu", "--bench", "otg", "--", "--warm-up-time", "1", "--measurement-time", "5", "--noplot"],
        env: &[],
        rows: &[
            Row {
                what: "online planner, 1000 random states: ours",
                find: Find::Criterion("otg 1000 random states/Trajectory::to_position"),
                goal: "",
            },
            Row {
                what: "the same states: Ruckig (rsruckig)",
                find: Find::Criterion("otg 1000 random states/rsruckig Ruckig::calculate"),
                goal: "",
            },
        ],
    },
    Run {
        name: "path",
        cargo: &["bench", "-p", "card-emu", "--bench", "path", "--", "--runs", "3"],
        env: &[],
        rows: &[
            Row {
                what: "path engine, dense curve: look-ahead and blending, µs a segment (median, range)",
                find: Find::Cells("look-ahead and blending (push + plan)", &[1, 2]),
                goal: "≤ 2 µs",
            },
            Row {
                what: "path engine, dense curve: whole engine with interpolation, µs a segment",
                find: Find::Cells("total (push + plan + move)", &[1, 2]),
                goal: "",
            },
            Row {
                what: "path engine, dense curve: path time against its offline bound",
                find: Find::Line("path time"),
                goal: "≤ 1.10",
            },
        ],
    },
    Run {
        name: "path_run",
        cargo: &["bench", "-p", "card-emu", "--bench", "path_run", "--", "corners", "streaming"],
        env: &[],
        rows: &[
            Row {
                what: "50 mm square at 100 mm/s, 10 µm corners: path time s, % of exact stop, deviation µm",
                find: Find::Cells("square 50 mm                 |     10 µm", &[2, 3, 4]),
                goal: "",
            },
            Row {
                what: "segments streamed from another process, a second (accepted, the path's rate, starvation)",
                find: Find::Cells("accepted, average rate", &[1]),
                goal: "≥ 10,000/s",
            },
        ],
    },
    Run {
        name: "pvt",
        cargo: &["bench", "-p", "card-emu", "--bench", "pvt_stream"],
        env: &[],
        rows: &[Row {
            what: "PVT points streamed from another process, a second",
            find: Find::Cells("the refills", &[1]),
            goal: "",
        }],
    },
    Run {
        name: "cam",
        cargo: &["bench", "--bench", "cam"],
        env: &[],
        rows: &[
            Row {
                what: "G2 circle, 1-inch radius, 100 mm/s: against its time-optimal bound",
                find: Find::Cells("G2 circle, 1-inch radius", &[1]),
                goal: "≤ 1.05×",
            },
            Row {
                what: "the circle as 10,000 chords, rounded to 4 decimals in inches",
                find: Find::Cells("10,000 chords, 4 decimals", &[1]),
                goal: "≤ 1.20× the G2",
            },
            Row {
                what: "one G1 of 25.4 mm against the axis's S-curve",
                find: Find::Cells("one G1 of 25.4 mm", &[1]),
                goal: "≤ 1.02×",
            },
            Row {
                what: "1,000 collinear pieces of it, one by one",
                find: Find::Cells("1,000 collinear pieces of it, one by one", &[1]),
                goal: "≤ 1.03× the G1",
            },
            Row {
                what: "3-axis finishing raster, 0.2 mm chords, mm to 3 decimals",
                find: Find::Cells("3-axis finishing raster", &[1]),
                goal: "every limit held",
            },
        ],
    },
    Run {
        name: "gcode",
        cargo: &["bench", "--bench", "gcode"],
        env: &[],
        rows: &[
            Row {
                what: "G-code interpreter, a 100,000-block CAM program read from its file",
                find: Find::Cells("interpreter, ", &[1]),
                goal: "",
            },
            Row {
                what: "`mcctl run` of it: to the first motion",
                find: Find::Cells("to the first motion", &[1]),
                goal: "",
            },
        ],
    },
];

/// The middle estimate of a criterion benchmark's `time: [lo mid hi]`.
fn criterion_median(out: &str, id: &str) -> Option<String> {
    let at = out.find(id)?;
    let rest = &out[at + id.len()..];
    let time = rest.find("time:")?;
    let inner = rest[time..].split_once('[')?.1.split_once(']')?.0;
    let words: Vec<&str> = inner.split_whitespace().collect();
    // "1.0 µs 1.1 µs 1.2 µs": the value and unit in the middle
    (words.len() == 6).then(|| format!("{} {}", words[2], words[3]))
}

fn find(out: &str, f: &Find) -> Option<String> {
    match f {
        Find::Criterion(id) => criterion_median(out, id),
        Find::Line(text) => out
            .lines()
            .find(|l| l.contains(text))
            .map(|l| l.trim().to_string()),
        Find::Cells(text, cells) => {
            let line = out.lines().find(|l| l.contains(text))?;
            let all: Vec<&str> = line
                .trim()
                .trim_matches('|')
                .split('|')
                .map(str::trim)
                .collect();
            let picked: Option<Vec<&str>> = cells.iter().map(|&c| all.get(c).copied()).collect();
            Some(picked?.join(", "))
        }
    }
}

/// The machine, as the dashboard names it: CPU model, cores, kernel.
fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, m)| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease").unwrap_or_default();
    format!("{cpu}, {cores} cores, Linux {}", kernel.trim())
}

fn git(root: &Path, args: &[&str]) -> String {
    Command::new("git")
        .args(args)
        .current_dir(root)
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default()
}

const BEGIN: &str = "<!-- dashboard: cargo xtask bench --write -->";
const END: &str = "<!-- end of dashboard -->";

pub fn command(root: &Path, args: &[String]) -> ExitCode {
    let write = args.iter().any(|a| a == "--write");
    let only: Vec<&str> = args
        .windows(2)
        .filter(|w| w[0] == "--only")
        .map(|w| w[1].as_str())
        .collect();
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut table = vec![
        "| figure | today | goal | command |".to_string(),
        "|---|---|---|---|".to_string(),
    ];
    let mut missing = vec![];
    for run in RUNS {
        if !only.is_empty() && !only.contains(&run.name) {
            continue;
        }
        eprintln!("== {}: cargo {}", run.name, run.cargo.join(" "));
        let out = Command::new(&cargo)
            .args(run.cargo)
            .envs(run.env.iter().copied())
            .current_dir(root)
            .output();
        let out = match out {
            Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).into_owned(),
            Ok(o) => {
                eprintln!("{}", String::from_utf8_lossy(&o.stderr));
                eprintln!("the {} bench failed ({})", run.name, o.status);
                return ExitCode::FAILURE;
            }
            Err(e) => {
                eprintln!("cannot run cargo: {e}");
                return ExitCode::FAILURE;
            }
        };
        let shown: String = run
            .cargo
            .join(" ")
            .replace(CRITERION_QUICK, "")
            .trim_end()
            .trim_end_matches(" --")
            .to_string();
        for row in run.rows {
            let figure = find(&out, &row.find).unwrap_or_else(|| {
                missing.push(format!("{}: {}", run.name, row.what));
                "(not printed)".into()
            });
            let line = format!(
                "| {} | {} | {} | `cargo {}` |",
                row.what,
                figure.replace('|', "/"),
                row.goal,
                shown
            );
            println!("{line}");
            table.push(line);
        }
    }
    if !missing.is_empty() {
        eprintln!("rows whose figure the bench no longer prints:");
        for m in &missing {
            eprintln!("  {m}");
        }
        return ExitCode::FAILURE;
    }
    if write {
        if !only.is_empty() {
            eprintln!("--write rewrites the whole dashboard: run it without --only");
            return ExitCode::from(2);
        }
        let path = root.join("BENCHMARKS.md");
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        let (Some(b), Some(e)) = (text.find(BEGIN), text.find(END)) else {
            eprintln!("BENCHMARKS.md has no dashboard markers ({BEGIN} … {END})");
            return ExitCode::FAILURE;
        };
        let head = format!(
            "{BEGIN}\nMeasured {} at commit {} on {}.\n\n",
            git(root, &["log", "-1", "--format=%cs"]),
            git(root, &["rev-parse", "--short", "HEAD"]),
            machine()
        );
        let new = format!("{}{head}{}\n{}", &text[..b], table.join("\n"), &text[e..]);
        if let Err(e) = std::fs::write(&path, new) {
            eprintln!("cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
        eprintln!("wrote the dashboard into BENCHMARKS.md");
    }
    ExitCode::SUCCESS
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn criterion_medians_and_table_cells_are_found() {
        let out = "firmware tick, 8 moving axes + plant\n                        time:   [1.0123 µs 1.0456 µs 1.0789 µs]\n\
                   | look-ahead and blending (push + plan)  |   0.861 |   0.825 – 0.969   |\n";
        assert_eq!(
            find(
                out,
                &Find::Criterion("firmware tick, 8 moving axes + plant")
            )
            .as_deref(),
            Some("1.0456 µs")
        );
        assert_eq!(
            find(out, &Find::Cells("look-ahead and blending", &[1, 2])).as_deref(),
            Some("0.861, 0.825 – 0.969")
        );
        assert_eq!(
            find(out, &Find::Cells("look-ahead and blending", &[7])),
            None
        );
        assert_eq!(find(out, &Find::Criterion("not there")), None);
    }

    /// Every run's shown command is its cargo arguments without the criterion tuning.
    #[test]
    fn criterion_runs_use_the_quick_settings() {
        for run in RUNS {
            let joined = run.cargo.join(" ");
            if run
                .rows
                .iter()
                .any(|r| matches!(r.find, Find::Criterion(_)))
            {
                assert!(joined.ends_with(CRITERION_QUICK), "{}", run.name);
            }
        }
    }
}
