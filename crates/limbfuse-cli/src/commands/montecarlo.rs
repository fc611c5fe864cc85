//! `limbfuse montecarlo`: paper 000 Fig. 9 on simulated walking.

use std::io::Write;

use anyhow::{anyhow, Context, Result};
use limbfuse_io::provenance::{COMMAND_KEY, LIMBFUSE_VERSION, VERSION_KEY};
use limbfuse_sim::WalkingConfig;
use limbfuse_workflows::monte_carlo::{levels_from_spec, monte_carlo, write_csv, MonteCarloConfig};
use limbfuse_workflows::monte_carlo_plot::render_svg;

use crate::cli::MonteCarloArgs;

/// Parses `START:END:STEP` percent into fractions.
fn parse_levels(text: &str) -> Result<Vec<f64>> {
    levels_from_spec(text).map_err(|m| anyhow!("--levels: {m}"))
}

/// The provenance lines of the CSV and SVG (docs/OUTPUTS.md section 3): the
/// limbfuse version, the command with every setting (the defaults
/// included; file names only, as an estimate's `# command:`), and the
/// seeds of the simulated trials.
fn provenance(a: &MonteCarloArgs) -> Vec<(&'static str, String)> {
    let mut command = format!(
        "limbfuse montecarlo --runs {} --levels {} --seed {} --speed {} --duration {}",
        a.runs,
        super::shell_word(&a.levels),
        a.seed,
        a.speed,
        a.duration
    );
    if a.cap.force {
        command += " --force";
    }
    command += &format!(" -o {}", super::file_word(&a.output));
    if let Some(svg) = &a.svg {
        command += &format!(" --svg {}", super::file_word(svg));
    }
    let last = a.seed.wrapping_add(a.runs.saturating_sub(1) as u64);
    vec![
        (VERSION_KEY, LIMBFUSE_VERSION.to_string()),
        (COMMAND_KEY, command),
        (
            "trial_seeds",
            format!(
                "{} to {last} (run r: --seed + r; its parameter errors from the stream keyed by (--seed, r, level))",
                a.seed
            ),
        ),
    ]
}

/// Runs the study and writes the CSV (and SVG).
pub fn run(a: &MonteCarloArgs) -> Result<()> {
    let levels = parse_levels(&a.levels)?;
    super::refuse_stdout(&a.output)?;
    if let Some(svg) = &a.svg {
        super::refuse_stdout(svg)?;
    }
    super::refuse_overwrites(&[], &[("-o", Some(&a.output)), ("--svg", a.svg.as_deref())])?;
    crate::bounds::simulated_trial(
        a.duration,
        "the IMU rate",
        WalkingConfig::default().imu_rate_hz,
        a.cap.force,
    )?;
    let cfg = MonteCarloConfig {
        runs: a.runs,
        levels,
        seed: a.seed,
        trial: WalkingConfig {
            speed_mps: a.speed,
            duration_s: a.duration,
            ..WalkingConfig::default()
        },
    };
    super::simulate::check_walking(&cfg.trial)?;
    // Both outputs are opened before the study (a folder that does not
    // exist fails now, not after it) and renamed into place together, once
    // both are written (an audit: a failing --svg left a new -o behind).
    let mut out = super::create_file(&a.output)?;
    let svg_out = a.svg.as_deref().map(super::create_file).transpose()?;
    let bar = crate::progress::bar(
        a.runs as u64,
        "montecarlo {bar:30} {pos}/{len} runs [{elapsed} < {eta}]",
    );
    let rows = monte_carlo(&cfg, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let provenance = provenance(a);
    write_csv(&rows, &provenance, &mut out)
        .with_context(|| format!("{}: cannot write", a.output.display()))?;
    if let (Some(svg), Some(mut file)) = (&a.svg, svg_out) {
        let title = format!(
            "{} runs per level, {} m/s, {} s trials",
            a.runs, a.speed, a.duration
        );
        let text = render_svg(&rows, svg, &title, &provenance).map_err(|e| anyhow!(e))?;
        file.write_all(text.as_bytes())
            .with_context(|| format!("{}: cannot write the plot", svg.display()))?;
        super::commit(out)?;
        super::commit(file)?;
    } else {
        super::commit(out)?;
    }
    println!(
        "{:<8}{:>10}{:>16}{:>12}",
        "method", "level %", "mean RMSE deg", "std deg"
    );
    for r in &rows {
        println!(
            "{:<8}{:>10.1}{:>16.3}{:>12.3}",
            r.method,
            r.level_pct(),
            r.mean_rmse_deg,
            r.std_rmse_deg
        );
    }
    eprintln!("wrote {}", a.output.display());
    if let Some(svg) = &a.svg {
        eprintln!(
            "wrote {} (mean RMSE against noise level, paper 000 Fig. 9)",
            svg.display()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::parse_levels;

    #[test]
    fn levels_parse_as_fractions() {
        let l = parse_levels("0:20:5").unwrap();
        assert_eq!(l, vec![0.0, 0.05, 0.1, 0.15, 0.2]);
        assert!(parse_levels("0:20").is_err());
        assert!(parse_levels("0:20:0").is_err());
        assert!(parse_levels("5:1:1").is_err());
        assert!(parse_levels("a:b:c").is_err());
    }
}
