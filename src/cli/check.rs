//! `linkdyn check MODEL`: validate and assemble; print the model's structure.

use super::{Failure, in_model};
use clap::Args;
use linkdyn::formulation::{Dae, DaeOptions};
use linkdyn::model::JointKind;
use linkdyn::output::format_for_people;
use std::path::PathBuf;

/// Arguments of `check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Model file (TOML).
    model: PathBuf,
    /// Override a model field: dotted path, array entries by name (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

/// Runs `check`.
pub fn run(args: &CheckArgs) -> Result<(), Failure> {
    let model = super::load_model(&args.model, &args.set, &[])?;
    let dae =
        Dae::new(&model, &DaeOptions::default()).map_err(|e| in_model(&args.model, e.into()))?;
    let a = dae.assembly();
    println!("model {} ({})", model.name, args.model.display());
    if !model.description.is_empty() {
        println!("  {}", model.description);
    }
    println!("bodies: {}", model.bodies.len());
    for (i, b) in model.bodies.iter().enumerate() {
        println!(
            "  {:<12} m = {} kg, I = {} kg·m², assembled x = {:.6} m, y = {:.6} m, phi = {:.6} rad",
            b.name,
            format_for_people(b.mass),
            format_for_people(b.inertia),
            a.q[3 * i],
            a.q[3 * i + 1],
            a.q[3 * i + 2]
        );
    }
    println!("joints: {}", model.joints.len());
    for j in &model.joints {
        let extra = match &j.kind {
            JointKind::Clearance(c) => {
                let film = match &c.lubrication {
                    Some(l) => format!(
                        ", lubricated: {} bearing, μ = {} Pa·s, L = {} m, contact below a film of {} m",
                        l.model.name(),
                        format_for_people(l.viscosity),
                        format_for_people(c.length.unwrap_or(0.0)),
                        format_for_people(l.contact_film_thickness)
                    ),
                    None => String::new(),
                };
                format!(
                    " (bearing on {}, journal on {}, c = {} m, R_J = {} m{film})",
                    model.frame_name(j.a.frame),
                    model.frame_name(j.b.frame),
                    format_for_people(c.clearance),
                    format_for_people(c.journal_radius)
                )
            }
            JointKind::PrismaticClearance(p) => {
                format!(
                    " (guide on {}, slider on {}, c = {} m, L = {} m, w = {} m, K = {} N/m^{})",
                    model.frame_name(j.a.frame),
                    model.frame_name(j.b.frame),
                    format_for_people(p.clearance),
                    format_for_people(p.slider_length),
                    format_for_people(p.slider_width),
                    format_for_people(p.stiffness),
                    format_for_people(p.exponent)
                ) + &guide_ends(p)
            }
            _ => String::new(),
        };
        println!(
            "  {:<12} {:<10} {}.{} – {}.{}{extra}",
            j.name,
            j.kind.type_name(),
            model.frame_name(j.a.frame),
            j.a.point,
            model.frame_name(j.b.frame),
            j.b.point
        );
    }
    if !model.parameters.is_empty() {
        let listed: Vec<String> = model
            .parameters
            .iter()
            .map(|(n, v)| format!("{n} = {}", format_for_people(*v)))
            .collect();
        println!("parameters: {}", listed.join(", "));
    }
    println!("drivers: {}", model.drivers.len());
    for d in &model.drivers {
        println!(
            "  {:<12} {} on joint {}, from {} rad",
            d.name,
            d.describe(),
            model.joint(d.joint).name,
            format_for_people(d.initial_angle)
        );
    }
    println!(
        "forces: {} (+ gravity [{}, {}] m/s²)",
        model.forces.len(),
        model.settings.gravity[0],
        model.settings.gravity[1]
    );
    for f in &model.forces {
        println!("  {:<12} {}", f.name(), f.type_name());
    }
    for o in &model.outputs {
        println!(
            "output point {} on {} at [{}, {}] m",
            o.name,
            model.frame_name(o.at.frame),
            o.at.local[0],
            o.at.local[1]
        );
    }
    let set = dae.constraints();
    let redundant: Vec<String> = dae
        .redundant_rows()
        .iter()
        .map(|&k| set.row_name(&model, k))
        .collect();
    println!(
        "coordinates: {}, constraint rows: {}, rank: {}, degrees of freedom: {}",
        dae.n_coordinates(),
        set.n_rows(),
        set.n_rows() - redundant.len(),
        dae.n_coordinates() - (set.n_rows() - redundant.len())
    );
    if redundant.is_empty() {
        println!("redundant constraints: none");
    } else {
        println!(
            "redundant constraints: {} (left out of the dynamics; their reactions are not unique)",
            redundant.join(", ")
        );
    }
    println!(
        "assembled in {} Newton iterations, max |Phi| = {:.3e}",
        a.iterations, a.residual
    );
    Ok(())
}

/// The guide's end stops of a prismatic-clearance joint for the joint list (empty without any).
fn guide_ends(p: &linkdyn::model::PrismaticClearanceSpec) -> String {
    let at = |s: Option<f64>| {
        s.map_or_else(
            || "none".to_string(),
            |s| format!("{} m", format_for_people(s)),
        )
    };
    if p.guide_start.is_none() && p.guide_end.is_none() {
        return String::new();
    }
    format!(", guide ends {} … {}", at(p.guide_start), at(p.guide_end))
}
