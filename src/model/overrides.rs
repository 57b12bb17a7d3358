//! `--set KEY=VALUE` overrides: a dotted path into the model file, array entries by name
//! (`drivers.motor.speed_rpm=3500`, `bodies.crank.mass=0.5`, `settings.gravity=[0, 0]`).
//!
//! Applied to the TOML document before it is deserialised, so every check that applies to the
//! file applies to an overridden value too.
//!
//! Switching a contact or friction law (`joints.B.friction.law=none`,
//! `joints.B.contact.law=hertz`, or a line-contact law's `joints.B.contact.damping=none`) also
//! drops the fields of that table the new law does not take
//! (the `coefficient` left behind by Ambrósio's law would otherwise be refused), and each drop
//! is reported as a note. A field set again by a later `--set` is then an error as in a file.

use super::error::{ModelError, abbreviate};
use super::laws;
use super::suggest::did_you_mean;
use toml::{Table, Value};

/// Most dot-separated parts of a `--set` path. A model's deepest field is about six parts down
/// (`joints.B.contact.law`); every part of a longer path would become a nested table, which
/// writing and reading the document back then recurse through (20 000 parts overflowed the
/// stack).
pub const MAX_PATH_PARTS: usize = 16;

/// Returns the model text with every override applied, in order, and the notes about fields
/// dropped by a switch of law.
pub fn apply(
    text: &str,
    file: &str,
    overrides: &[String],
) -> Result<(String, Vec<String>), ModelError> {
    let mut notes = Vec::new();
    let mut doc: Table = text
        .parse()
        .map_err(|e: toml::de::Error| ModelError::WholeFile {
            file: file.to_string(),
            message: e.message().trim().to_string(),
        })?;
    for assignment in overrides {
        let fail = |message: String| ModelError::Override {
            assignment: abbreviate(assignment),
            message,
        };
        let (path, raw_value) = assignment
            .split_once('=')
            .ok_or_else(|| fail("expected KEY=VALUE, e.g. drivers.motor.speed_rpm=3500".into()))?;
        let keys: Vec<&str> = path.trim().split('.').collect();
        if keys.len() > MAX_PATH_PARTS {
            return Err(fail(format!(
                "the path has {} parts; expected at most {MAX_PATH_PARTS} (the deepest field of a model file is a few levels down)",
                keys.len()
            )));
        }
        if keys.iter().any(|k| k.is_empty()) {
            return Err(fail(format!("empty key in path \"{}\"", path.trim())));
        }
        set(&mut doc, &keys, parse_value(raw_value.trim())).map_err(fail)?;
        if let Some(note) = drop_fields_of_old_law(&mut doc, &keys) {
            notes.push(format!("--set {}: {note}", assignment.trim()));
        }
    }
    let text = toml::to_string(&doc).map_err(|e| ModelError::WholeFile {
        file: file.to_string(),
        message: format!("cannot re-serialise the model after --set: {e}"),
    })?;
    Ok((text, notes))
}

/// After `keys` = `….contact.law` or `….friction.law` was set: removes the fields of that table
/// the new law does not take and says which. `None` if nothing was dropped, or if the law is
/// unknown (validation names it then).
fn drop_fields_of_old_law(doc: &mut Table, keys: &[&str]) -> Option<String> {
    if let [.., "contact", "damping"] = keys {
        return drop_restitution_of_undamped(doc, keys.get(..keys.len() - 1)?);
    }
    let (table_keys, kind) = match keys {
        [.., kind, "law"] if *kind == "contact" || *kind == "friction" => {
            (keys.get(..keys.len() - 1)?, *kind)
        }
        _ => return None,
    };
    let table = table_at(doc, table_keys)?;
    let law = table.get("law")?.as_str()?.to_string();
    let taken = laws::fields_of(
        if kind == "contact" {
            laws::CONTACT
        } else {
            laws::FRICTION
        },
        &law,
    )?;
    let dropped: Vec<String> = table
        .keys()
        .filter(|k| !taken.contains(&k.as_str()))
        .cloned()
        .collect();
    if dropped.is_empty() {
        return None;
    }
    let listed: Vec<String> = dropped
        .iter()
        .filter_map(|k| table.remove(k).map(|v| format!("{k} = {v}")))
        .collect();
    Some(format!(
        "dropped {} from {}, which {kind} law \"{law}\" does not take",
        listed.join(", "),
        table_keys.join(".")
    ))
}

/// After `….contact.damping=none`: removes the coefficient of restitution, which an undamped
/// (purely elastic) line-contact law does not take, as switching to the hertz law does.
fn drop_restitution_of_undamped(doc: &mut Table, table_keys: &[&str]) -> Option<String> {
    let table = table_at(doc, table_keys)?;
    if table.get("damping")?.as_str()? != "none" {
        return None;
    }
    let value = table.remove("restitution")?;
    Some(format!(
        "dropped restitution = {value} from {}, which damping \"none\" does not take",
        table_keys.join(".")
    ))
}

/// The table at the dotted `keys` (array entries by name), if there is one.
fn table_at<'t>(table: &'t mut Table, keys: &[&str]) -> Option<&'t mut Table> {
    let Some((first, rest)) = keys.split_first() else {
        return Some(table);
    };
    match table.get_mut(*first)? {
        Value::Table(inner) => table_at(inner, rest),
        Value::Array(items) => {
            let (name, rest) = rest.split_first()?;
            let item = items
                .iter_mut()
                .find(|i| i.get("name").and_then(Value::as_str) == Some(name))?;
            match item {
                Value::Table(inner) => table_at(inner, rest),
                _ => None,
            }
        }
        _ => None,
    }
}

/// A TOML value if the text is one (number, boolean, array, quoted string), otherwise the bare
/// text as a string (so `--set bodies.crank.name=arm` works without quotes).
fn parse_value(raw: &str) -> Value {
    format!("v = {raw}")
        .parse::<Table>()
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| Value::String(raw.to_string()))
}

fn set(table: &mut Table, keys: &[&str], value: Value) -> Result<(), String> {
    let Some((first, rest)) = keys.split_first() else {
        return Err("empty path".into());
    };
    if rest.is_empty() {
        table.insert((*first).to_string(), value);
        return Ok(());
    }
    let entry = table
        .entry((*first).to_string())
        .or_insert_with(|| Value::Table(Table::new()));
    match entry {
        Value::Table(inner) => set(inner, rest, value),
        Value::Array(items) => {
            let (name, rest) = rest.split_first().ok_or("missing entry name")?;
            let names: Vec<String> = items
                .iter()
                .filter_map(|i| i.get("name").and_then(Value::as_str).map(str::to_string))
                .collect();
            let item = items
                .iter_mut()
                .find(|i| i.get("name").and_then(Value::as_str) == Some(name))
                .ok_or_else(|| {
                    format!(
                        "no entry named \"{name}\" in {first}{}",
                        did_you_mean(name, names.iter().map(String::as_str))
                    )
                })?;
            match item {
                Value::Table(inner) if !rest.is_empty() => set(inner, rest, value),
                _ => Err(format!("{first}.{name} needs a field after it")),
            }
        }
        _ => Err(format!("\"{first}\" is a value, not a table")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOC: &str = "[model]\nname = \"m\"\n\n[[drivers]]\nname = \"motor\"\nspeed_rpm = 250.0\n";

    #[test]
    fn sets_array_entry_by_name_and_creates_tables() {
        let out = apply(
            DOC,
            "m.toml",
            &[
                "drivers.motor.speed_rpm=3500".into(),
                "settings.baumgarte.alpha=5".into(),
            ],
        );
        let (out, notes) = out.unwrap_or_default();
        assert!(notes.is_empty(), "{notes:?}");
        assert!(out.contains("speed_rpm = 3500"), "{out}");
        assert!(out.contains("alpha = 5"), "{out}");
    }

    #[test]
    fn unknown_entry_is_named_with_a_suggestion() {
        let err = apply(DOC, "m.toml", &["drivers.motr.speed_rpm=1".into()])
            .err()
            .map(|e| e.to_string());
        assert_eq!(
            err.as_deref(),
            Some(
                "--set drivers.motr.speed_rpm=1: no entry named \"motr\" in drivers: did you mean \"motor\"?"
            )
        );
    }
}
