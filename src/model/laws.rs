//! Which fields of `[joints.contact]` and `[joints.friction]` each law takes.
//!
//! One table for both the validation (a field the law does not take is an error in a file) and
//! `--set` (switching the law drops the fields only the old law took, with a note).

/// Contact laws and the fields of `[joints.contact]` each takes. Hertz is purely elastic, so it
/// takes no coefficient of restitution; the line-contact laws (johnson, liu) have their own
/// exponent and take the hysteresis factor as `damping`.
pub const CONTACT: &[(&str, &[&str])] = &[
    ("lankarani-nikravesh", &["law", "restitution", "exponent"]),
    ("hunt-crossley", &["law", "restitution", "exponent"]),
    ("flores", &["law", "restitution", "exponent"]),
    ("hertz", &["law", "exponent"]),
    ("johnson", &["law", "damping", "restitution"]),
    ("liu", &["law", "damping", "restitution"]),
];

/// Hysteresis factors a line-contact law can take as `damping`.
pub const DAMPING: &[&str] = &["lankarani-nikravesh", "hunt-crossley", "flores", "none"];

/// Film models of `[joints.lubrication]`.
pub const FILM_MODELS: &[&str] = &["short", "long"];

/// Friction laws and the fields of `[joints.friction]` each takes.
pub const FRICTION: &[(&str, &[&str])] = &[
    ("ambrosio", &["law", "coefficient", "v0", "v1"]),
    ("ambrosio-as-printed", &["law", "coefficient", "v0", "v1"]),
    ("none", &["law"]),
];

/// The fields `law` takes in `table` ([`CONTACT`] or [`FRICTION`]), if it is one of them.
pub fn fields_of(
    table: &[(&'static str, &'static [&'static str])],
    law: &str,
) -> Option<&'static [&'static str]> {
    table.iter().find(|(name, _)| *name == law).map(|(_, f)| *f)
}

/// The law names of `table`.
pub fn names(table: &[(&'static str, &'static [&'static str])]) -> Vec<&'static str> {
    table.iter().map(|(name, _)| *name).collect()
}
