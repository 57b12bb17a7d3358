//! Units of linkdyn's output columns, read from their names (`coupler.omega` → rad/s), for
//! axis labels.

/// The SI unit of an output column, from the last part of its name: `t` s; `.x .y .ex .ey
/// .delta` m; `.phi` rad; `.vx .vy` m/s; `.omega` rad/s; `.ax .ay` m/s²; `.alpha` rad/s²;
/// `.fx .fy .fn .ft` N; `.torque` N·m; `energy.*` J; `frequency_hz` Hz. Swept model
/// parameters (a bifurcation file's second column) by their field: `.clearance` m, `.mass` kg,
/// `*_rpm` rpm, `*_hz` Hz (the model file's SI fields and its unit-suffixed ones). `None` for
/// a name without a known unit (a dimensionless or user-named column).
pub fn unit_of(column: &str) -> Option<&'static str> {
    if column == "t" {
        return Some("s");
    }
    if column == "frequency_hz" || column.ends_with("_hz") {
        return Some("Hz");
    }
    if column.ends_with("_rpm") {
        return Some("rpm");
    }
    if column.starts_with("energy.") {
        return Some("J");
    }
    let last = column.rsplit('.').next().unwrap_or(column);
    Some(match last {
        "x" | "y" | "ex" | "ey" | "delta" | "clearance" => "m",
        "mass" => "kg",
        "phi" => "rad",
        "vx" | "vy" => "m/s",
        "omega" => "rad/s",
        "ax" | "ay" => "m/s²",
        "alpha" => "rad/s²",
        "fx" | "fy" | "fn" | "ft" => "N",
        "torque" => "N·m",
        _ => return None,
    })
}

/// An axis label: the column name with its unit in parentheses, e.g. `motor.torque (N·m)`;
/// the bare name when the unit is unknown.
pub fn axis_label(column: &str) -> String {
    match unit_of(column) {
        Some(u) => format!("{column} ({u})"),
        None => column.to_string(),
    }
}

/// The unit of the time derivative of a quantity in `unit` (`m` → `m/s`, `rad` → `rad/s`,
/// `rad/s` → `rad/s²`).
pub fn rate_unit(unit: &str) -> String {
    if let Some(base) = unit.strip_suffix("/s") {
        format!("{base}/s²")
    } else if unit.ends_with("/s²") {
        format!("({unit})/s")
    } else {
        format!("{unit}/s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_follow_the_column_suffix() {
        for (name, unit) in [
            ("t", Some("s")),
            ("coupler.phi", Some("rad")),
            ("coupler.omega", Some("rad/s")),
            ("coupler.alpha", Some("rad/s²")),
            ("B.ex", Some("m")),
            ("B.fn", Some("N")),
            ("O2.fy", Some("N")),
            ("motor.torque", Some("N·m")),
            ("frequency_hz", Some("Hz")),
            ("joints.B.clearance", Some("m")),
            ("drivers.motor.speed_rpm", Some("rpm")),
            ("bodies.crank.mass", Some("kg")),
            ("amplitude", None),
            ("lambda", None),
        ] {
            assert_eq!(unit_of(name), unit, "{name}");
        }
        assert_eq!(axis_label("motor.torque"), "motor.torque (N·m)");
        assert_eq!(axis_label("lambda"), "lambda");
        assert_eq!(rate_unit("m"), "m/s");
        assert_eq!(rate_unit("rad/s"), "rad/s²");
    }
}
