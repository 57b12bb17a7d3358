//! `linkdyn wear MODEL --turns N --update-every M --out DIR`: Archard wear of the model's worn
//! clearance joint (the one with `[joints.wear]`) over N driver turns, the bearing profile
//! updated every M turns (`linkdyn::studies::wear`). Writes DIR/wear.csv (the depth per bin
//! after every update, long format), DIR/wear.json (settings, summary, provenance) and
//! DIR/profile.svg (the worn profile, polar, magnified), each whole or not at all.

use super::poincare::{ModelArgs, bad, csv_head, write_whole};
use super::{Failure, in_model};
use clap::Args;
use linkdyn::output::format_number;
use linkdyn::plot::render;
use linkdyn::studies::{WearRequest, WearResult, wear};
use std::path::{Path, PathBuf};

/// Arguments of `wear`.
#[derive(Debug, Args)]
pub struct WearArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Driver turns to run in all (a whole number ≥ 1).
    #[arg(long)]
    turns: usize,
    /// Update the bearing profile every M driver turns (≥ 1; the last interval may be shorter).
    #[arg(long, default_value_t = 1)]
    update_every: usize,
    /// Output folder (created if missing): wear.csv, wear.json, profile.svg.
    #[arg(long)]
    out: PathBuf,
}

/// Runs `wear`.
pub fn run(args: &WearArgs) -> Result<(), Failure> {
    args.model.no_t_end()?;
    if args.model.solve.revs.is_some() {
        return Err(bad(
            "revs",
            "the wear study counts its turns with `turns`: give `turns` instead",
        ));
    }
    let sim = args.model.simulation(args.turns.max(1) as f64)?;
    let dir = &args.out;
    if dir.exists() && !dir.is_dir() {
        return Err(Failure::from(linkdyn::output::OutputError::Target {
            path: dir.display().to_string(),
            reason: "is not a folder; expected a folder for wear.csv, wear.json and profile.svg"
                .into(),
        }));
    }
    let csv = dir.join("wear.csv");
    let json = dir.join("wear.json");
    let svg = dir.join("profile.svg");
    let request = WearRequest {
        turns: args.turns,
        update_every: args.update_every,
    };
    let result = wear(&sim, request).map_err(|e| in_model(&args.model.model, e))?;
    std::fs::create_dir_all(dir).map_err(|e| {
        Failure::from(linkdyn::output::OutputError::Io {
            path: dir.display().to_string(),
            reason: e.to_string(),
        })
    })?;
    write_whole(&csv, &args.model.model, &csv_text(&result))?;
    write_whole(&json, &args.model.model, &json_text(&result)?)?;
    write_figure(&svg, &result)?;
    let s = &result.summary;
    println!(
        "joint {}: {} turns, profile updated every {} ({} updates)",
        result.joint,
        result.turns,
        result.update_every,
        result.updates.len() - 1
    );
    println!(
        "deepest wear {} m at {} deg (bearing frame); mean {} m; worn volume {} m^3 ({} m^2 per unit length)",
        format_number(s.max_depth),
        format_number(s.max_depth_angle.to_degrees()),
        format_number(s.mean_depth),
        format_number(s.worn_volume),
        format_number(s.worn_area)
    );
    eprintln!(
        "wrote {}, {} and {}",
        csv.display(),
        json.display(),
        svg.display()
    );
    Ok(())
}

/// `update,t,turns,bin,theta_rad,depth_m`: one row per update and bin.
fn csv_text(r: &WearResult) -> String {
    let mut text = csv_head(
        "update,t,turns,bin,theta_rad,depth_m",
        r.provenance.clone(),
        &r.settings(),
    );
    for u in &r.updates {
        for (i, (theta, h)) in r.bin_centres.iter().zip(&u.depth).enumerate() {
            text.push_str(&format!(
                "{},{},{},{i},{},{}\n",
                u.index,
                format_number(u.t),
                format_number(u.turns),
                format_number(*theta),
                format_number(*h)
            ));
        }
    }
    text
}

/// wear.json: [`WearResult::summary_json`].
fn json_text(r: &WearResult) -> Result<String, Failure> {
    serde_json::to_string_pretty(&r.summary_json())
        .map(|s| s + "\n")
        .map_err(|e| bad("out", format!("cannot encode wear.json: {e}")))
}

/// profile.svg: the unworn circle, the profile halfway and the final one.
fn write_figure(path: &Path, r: &WearResult) -> Result<(), Failure> {
    let last = r.updates.len() - 1;
    let mut picks = vec![last];
    if last >= 2 {
        picks.insert(0, last / 2);
    }
    let profiles: Vec<(String, &[f64])> = picks
        .iter()
        .filter_map(|&i| r.updates.get(i))
        .map(|u| {
            (
                format!("after {} turns", format_number(u.turns)),
                u.depth.as_slice(),
            )
        })
        .collect();
    let fig = linkdyn::plot::wear::worn_profile(&r.joint, r.clearance, &r.bin_centres, &profiles);
    render(&fig, path)?;
    Ok(())
}
