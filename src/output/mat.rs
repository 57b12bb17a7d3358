//! The MAT result file (`linkdyn run --format mat`): a MATLAB Level-5 MAT-file, written without
//! MATLAB, that `d = load('F.mat')` reads in one line — one double column vector per column
//! (`d.t`, `d.coupler_phi`, …), the provenance as JSON text (`jsondecode(d.provenance)`) and
//! two char matrices that map the MATLAB names back to linkdyn's column names.
//!
//! # Names
//! A MATLAB variable name is a letter followed by letters, digits and `_`, at most 63
//! characters ([`MAX_NAME_LEN`]), and not a keyword. [`matlab_name`] turns a column name into
//! one: every other character (the `.` between the parts, a `-` of a model name) becomes `_`;
//! a name that does not start with a letter (a body named `2`) or is a keyword gets an `x` in
//! front. So `coupler.phi` → `coupler_phi`, `2.x` → `x2_x`. The rule is not injective
//! (`a-b.x` and `a_b.x` both give `a_b_x`), and MATLAB truncates longer names silently on
//! `load`, so [`matlab_names`] refuses, before the run, two columns that meet in one name, a
//! column that meets a fixed variable (`t`, `provenance`, `columns`, `names`) and a name longer
//! than 63 characters, naming the columns: every variable of a file stands for exactly one
//! column.
//!
//! # Layout
//! Little-endian throughout. The 128-byte header: 116 bytes of text (`MATLAB 5.0 MAT-file,
//! written by linkdyn <version>`, padded with spaces; no date, so that the same run gives a
//! byte-identical file), 8 zero bytes (no subsystem data), the version `0x0100` and the
//! endian indicator `IM`. Then one `miMATRIX` data element per variable, in this order:
//!
//! | variable | class | dimensions | content |
//! |---|---|---|---|
//! | `t`, then one per column | double | N × 1 | the samples (`miDOUBLE`) |
//! | `provenance` | char | 1 × L | the provenance as JSON (UTF-16 code units, `miUINT16`) |
//! | `columns` | char | (1 + C) × W | linkdyn's names, `t` first, one per row, padded with spaces |
//! | `names` | char | (1 + C) × W′ | the MATLAB names in the same rows |
//!
//! Each element is its tag (`miMATRIX` = 14 and its byte count), then the sub-elements array
//! flags (`miUINT32`: the class, no complex/global/logical flag), dimensions (`miINT32`), array
//! name (`miINT8`) and real part, each a tag and its data padded to a multiple of 8 bytes.
//! Nothing is compressed (`miCOMPRESSED` is MATLAB 7). A Level-5 variable holds at most 2 GiB
//! (a larger one needs MATLAB's HDF5-based 7.3 format): a column of that size is refused
//! before the run ([`check_mat`]).
//!
//! Like the NPZ, the MAT-file is written after the run from the columns kept in memory (each
//! element's tag holds its length first).
//!
//! # References
//! 1. The MathWorks, *MAT-File Format*, MATLAB 7 (2011), chapter 1, "Level 5 MAT-File
//!    Format": the header (Figure 1-1), data element tags and the small data element format
//!    (Table 1-1, data types), `miMATRIX` (array flags, Table 1-3, array classes).
//! 2. The MathWorks, MATLAB documentation, `save` (version 7 and earlier: 2 GB per variable),
//!    `namelengthmax` (63) and `iskeyword`.

use super::{OutputError, io_error};
use crate::simulation::{Columns, Provenance};
use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

/// Longest MATLAB variable name (`namelengthmax`).
pub const MAX_NAME_LEN: usize = 63;

/// The variables written beside the columns, in file order after them: the provenance and the
/// two name matrices. `t` comes first, before the columns.
pub const FIXED_VARIABLES: [&str; 4] = ["t", "provenance", "columns", "names"];

/// The words MATLAB's `iskeyword` lists: a variable (or struct field) of that name cannot be
/// addressed.
const KEYWORDS: [&str; 20] = [
    "break",
    "case",
    "catch",
    "classdef",
    "continue",
    "else",
    "elseif",
    "end",
    "for",
    "function",
    "global",
    "if",
    "otherwise",
    "parfor",
    "persistent",
    "return",
    "spmd",
    "switch",
    "try",
    "while",
];

/// Largest data element, tag included: MATLAB's limit on a Level-5 variable.
const MAX_ELEMENT_BYTES: u64 = 1 << 31;

// Data types and array classes (reference 1, tables 1-1 and 1-3).
const MI_INT8: u32 = 1;
const MI_UINT16: u32 = 4;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_DOUBLE: u32 = 9;
const MI_MATRIX: u32 = 14;
const MX_CHAR_CLASS: u32 = 4;
const MX_DOUBLE_CLASS: u32 = 6;

/// The MATLAB variable name of column `column` by the rule of the module doc (not yet checked
/// for length or collisions: see [`matlab_names`]).
pub fn matlab_name(column: &str) -> String {
    let mut name: String = column
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    if !name.starts_with(|c: char| c.is_ascii_alphabetic()) || KEYWORDS.contains(&name.as_str()) {
        name.insert(0, 'x');
    }
    name
}

/// The MATLAB names of the columns `names` (without `t`), in order. Errors
/// ([`OutputError::Target`], naming `target`): two columns with one MATLAB name, a column whose
/// name is one of [`FIXED_VARIABLES`], or a name longer than [`MAX_NAME_LEN`].
pub fn matlab_names(target: &Path, names: &[String]) -> Result<Vec<String>, OutputError> {
    let refuse = |reason: String| OutputError::Target {
        path: target.display().to_string(),
        reason,
    };
    let mut owner: HashMap<String, &str> = HashMap::new();
    for fixed in FIXED_VARIABLES {
        owner.insert(fixed.to_string(), fixed);
    }
    let mut out = Vec::with_capacity(names.len());
    for column in names {
        let name = matlab_name(column);
        if name.len() > MAX_NAME_LEN {
            return Err(refuse(format!(
                "column {column} would be the MATLAB variable {name} of {} characters; MATLAB names have at most {MAX_NAME_LEN} (longer ones are cut on load): shorten the name in the model, or use --format csv or npz",
                name.len()
            )));
        }
        if let Some(first) = owner.get(&name) {
            let first = if FIXED_VARIABLES.contains(first) {
                format!("the variable {first} every MAT result file has")
            } else {
                format!("column {first}")
            };
            return Err(refuse(format!(
                "column {column} and {first} would both be the MATLAB variable {name} (a MATLAB name has only letters, digits and '_'; the others become '_'): rename one in the model, or use --format csv or npz"
            )));
        }
        owner.insert(name.clone(), column);
        out.push(name);
    }
    Ok(out)
}

/// Bytes of a data element whose data is `n` bytes: the 8-byte tag and the data padded to 8.
fn element_bytes(n: u64) -> u64 {
    8 + n.div_ceil(8) * 8
}

/// Bytes of an `miMATRIX` element (tag included) named `name`, `dims.len()` dimensions, with
/// `data` bytes of real part.
fn matrix_bytes(name: &str, dims: usize, data: u64) -> u64 {
    8 + element_bytes(8)
        + element_bytes(4 * dims as u64)
        + element_bytes(name.len() as u64)
        + element_bytes(data)
}

/// The refusal of a variable of `bytes` bytes.
fn too_large(target: &Path, what: &str, bytes: u64) -> OutputError {
    OutputError::Target {
        path: target.display().to_string(),
        reason: format!(
            "{what} would take {:.2} GB in a MAT-file; a Level-5 MAT-file variable holds at most 2 GiB (MATLAB needs its -v7.3 format beyond): use --format csv (or npz below 4 GiB), or raise --dt",
            bytes as f64 / 1e9
        ),
    }
}

/// Checks, before a run, that a MAT-file of `samples` samples of `t` and the columns `names`
/// can be written: every column has its own valid MATLAB name ([`matlab_names`]) and no
/// variable reaches 2 GiB. `target` names the file in the error. Errors:
/// [`OutputError::Target`].
pub fn check_mat(target: &Path, samples: usize, names: &[String]) -> Result<(), OutputError> {
    let matlab = matlab_names(target, names)?;
    // The longest name makes the largest column; the name matrices are rows of short names.
    let longest = matlab.iter().map(String::as_str).max_by_key(|n| n.len());
    let name = longest.unwrap_or("t");
    let bytes = matrix_bytes(name, 2, 8 * samples as u64);
    if bytes >= MAX_ELEMENT_BYTES {
        return Err(too_large(
            target,
            &format!("a column of {samples} samples"),
            bytes,
        ));
    }
    Ok(())
}

/// A char matrix: its rows as UTF-16 code units (as MATLAB's `char` holds them), padded with
/// spaces to the longest; returns (rows, width, column-major data).
fn char_matrix<'a>(rows: impl Iterator<Item = &'a str>) -> (usize, usize, Vec<u16>) {
    let rows: Vec<Vec<u16>> = rows.map(|r| r.encode_utf16().collect()).collect();
    let width = rows.iter().map(Vec::len).max().unwrap_or(0);
    let mut data = Vec::with_capacity(rows.len() * width);
    for k in 0..width {
        for row in &rows {
            data.push(row.get(k).copied().unwrap_or(u16::from(b' ')));
        }
    }
    (rows.len(), width, data)
}

/// The 128-byte file header for linkdyn `version`.
fn header(version: &str) -> [u8; 128] {
    let mut h = [b' '; 128];
    let text = format!("MATLAB 5.0 MAT-file, written by linkdyn {version}");
    // The text is for people reading the file's first bytes: printable ASCII, cut to fit.
    for (slot, b) in h[..116].iter_mut().zip(
        text.bytes()
            .map(|b| if b.is_ascii_graphic() { b } else { b' ' }),
    ) {
        *slot = b;
    }
    // No subsystem data; then the version 0x0100 and "IM" (reads "MI" as a little-endian u16).
    h[116..124].fill(0);
    h[124..126].copy_from_slice(&0x0100u16.to_le_bytes());
    h[126..128].copy_from_slice(b"IM");
    h
}

/// Writes the tag of a data element of type `ty` with `n` data bytes.
fn tag<W: Write>(out: &mut W, ty: u32, n: u64) -> std::io::Result<()> {
    // Every element was checked below 2 GiB before writing.
    let n = u32::try_from(n).map_err(|_| std::io::Error::other("data element over 4 GiB"))?;
    out.write_all(&ty.to_le_bytes())?;
    out.write_all(&n.to_le_bytes())
}

/// Writes the zero bytes that pad `n` data bytes to a multiple of 8.
fn pad<W: Write>(out: &mut W, n: u64) -> std::io::Result<()> {
    let zeros = [0u8; 8];
    let k = (n.div_ceil(8) * 8 - n) as usize;
    out.write_all(&zeros[..k])
}

/// Writes the head of an `miMATRIX` element up to its real part's tag: the element's tag,
/// array flags of `class`, dimensions `dims`, the name and the tag of `data` bytes of type `ty`.
fn matrix_head<W: Write>(
    out: &mut W,
    name: &str,
    class: u32,
    dims: [usize; 2],
    ty: u32,
    data: u64,
) -> std::io::Result<()> {
    let total = matrix_bytes(name, dims.len(), data);
    tag(out, MI_MATRIX, total - 8)?;
    tag(out, MI_UINT32, 8)?;
    out.write_all(&class.to_le_bytes())?;
    out.write_all(&0u32.to_le_bytes())?;
    tag(out, MI_INT32, 8)?;
    for d in dims {
        let d = i32::try_from(d).map_err(|_| std::io::Error::other("dimension over 2^31"))?;
        out.write_all(&d.to_le_bytes())?;
    }
    tag(out, MI_INT8, name.len() as u64)?;
    out.write_all(name.as_bytes())?;
    pad(out, name.len() as u64)?;
    tag(out, ty, data)
}

/// Writes an N × 1 double variable.
fn write_column<W: Write>(out: &mut W, name: &str, v: &[f64]) -> std::io::Result<()> {
    matrix_head(
        out,
        name,
        MX_DOUBLE_CLASS,
        [v.len(), 1],
        MI_DOUBLE,
        8 * v.len() as u64,
    )?;
    let mut buf = Vec::with_capacity(8 * 1024);
    for chunk in v.chunks(1024) {
        buf.clear();
        for x in chunk {
            buf.extend_from_slice(&x.to_le_bytes());
        }
        out.write_all(&buf)?;
    }
    // 8-byte values end on a multiple of 8: no padding.
    Ok(())
}

/// Writes a char variable of `rows` × `width` UTF-16 code units (column-major).
fn write_chars<W: Write>(
    out: &mut W,
    name: &str,
    (rows, width, data): (usize, usize, Vec<u16>),
) -> std::io::Result<()> {
    let n = 2 * data.len() as u64;
    matrix_head(out, name, MX_CHAR_CLASS, [rows, width], MI_UINT16, n)?;
    let bytes: Vec<u8> = data.iter().flat_map(|c| c.to_le_bytes()).collect();
    out.write_all(&bytes)?;
    pad(out, n)
}

/// Writes the MAT-file of a run to `out`: `t`, one variable per column of `names` (the columns
/// of `data`, in order), `provenance`, `columns` and `names` (module doc). `path` names the
/// file in errors.
///
/// Errors: [`OutputError::Target`] for names that [`matlab_names`] refuses or a variable of
/// 2 GiB or more (nothing written then), [`OutputError::Io`] for a failed write.
pub fn write_mat<W: Write>(
    out: &mut W,
    path: &Path,
    provenance: &Provenance,
    names: &[String],
    data: &Columns,
) -> Result<(), OutputError> {
    check_mat(path, data.t.len(), names)?;
    let matlab = matlab_names(path, names)?;
    let provenance_json = serde_json::to_string(provenance).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        reason: format!("cannot serialise the provenance: {e}"),
    })?;
    let provenance_chars = char_matrix(std::iter::once(provenance_json.as_str()));
    let columns = char_matrix(std::iter::once("t").chain(names.iter().map(String::as_str)));
    let variables = char_matrix(std::iter::once("t").chain(matlab.iter().map(String::as_str)));
    for (name, (rows, width, _)) in [
        ("provenance", &provenance_chars),
        ("columns", &columns),
        ("names", &variables),
    ] {
        let bytes = matrix_bytes(name, 2, 2 * (rows * width) as u64);
        if bytes >= MAX_ELEMENT_BYTES {
            return Err(too_large(path, &format!("the variable {name}"), bytes));
        }
    }
    let write = || -> std::io::Result<()> {
        out.write_all(&header(&provenance.linkdyn_version))?;
        write_column(out, "t", &data.t)?;
        for (name, column) in matlab.iter().zip(&data.columns) {
            write_column(out, name, column)?;
        }
        write_chars(out, "provenance", provenance_chars)?;
        write_chars(out, "columns", columns)?;
        write_chars(out, "names", variables)
    };
    write().map_err(|e| io_error(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelSource;

    fn strings(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn names_follow_the_documented_rule() {
        for (column, name) in [
            ("coupler.phi", "coupler_phi"),
            ("B.fx", "B_fx"),
            ("energy.contact_elastic", "energy_contact_elastic"),
            ("a-1.x", "a_1_x"),
            ("2.x", "x2_x"),
            ("_p", "x_p"),
            ("end", "xend"),
            ("endx", "endx"),
            ("φ.x", "x__x"),
        ] {
            assert_eq!(matlab_name(column), name, "{column}");
        }
    }

    #[test]
    fn collisions_and_long_names_are_refused_with_both_columns_named() {
        let target = Path::new("r.mat");
        let err = |names: &[&str]| match matlab_names(target, &strings(names)) {
            Ok(v) => panic!("{names:?} accepted as {v:?}"),
            Err(e) => e.to_string(),
        };
        let e = err(&["a.x", "a-b.x", "a_b.x"]);
        assert!(
            e.contains("column a_b.x and column a-b.x would both be the MATLAB variable a_b_x"),
            "{e}"
        );
        let e = err(&["names"]);
        assert!(
            e.contains("the variable names every MAT result file has"),
            "{e}"
        );
        let long = format!("{}.x", "p".repeat(62));
        let e = err(&[long.as_str()]);
        assert!(e.contains("of 64 characters"), "{e}");
        // 63 characters is MATLAB's own limit, so it passes.
        let fits = format!("{}.x", "p".repeat(61));
        assert!(matlab_names(target, &strings(&[fits.as_str()])).is_ok());
    }

    #[test]
    fn a_column_of_2_gib_is_refused_before_the_run() {
        let names = strings(&["crank.phi"]);
        // 8 bytes a sample: 2^28 samples is 2 GiB of data alone.
        assert!(check_mat(Path::new("r.mat"), (1 << 28) - 16, &names).is_ok());
        let e = check_mat(Path::new("r.mat"), 1 << 28, &names).map_err(|e| e.to_string());
        assert!(
            e.as_ref().is_err_and(|e| e.contains("at most 2 GiB")),
            "{e:?}"
        );
    }

    #[test]
    fn elements_are_8_byte_aligned_and_their_lengths_add_up() {
        let provenance = Provenance {
            linkdyn_version: "v1\n".into(),
            model: ModelSource {
                path: "m.toml".into(),
                sha256: "0".into(),
                overrides: vec![],
            },
            settings: Default::default(),
        };
        let names = strings(&["a.x", "bb.y"]);
        let data = Columns {
            t: vec![0.0, 0.5, 1.0],
            columns: vec![vec![1.0, 2.0, 3.0], vec![-1.0, 0.25, f64::NAN]],
            constraint_violation: vec![0.0; 3],
            events: Vec::new(),
        };
        let mut bytes = Vec::new();
        assert!(write_mat(&mut bytes, Path::new("r.mat"), &provenance, &names, &data).is_ok());
        assert!(bytes.starts_with(b"MATLAB 5.0 MAT-file, written by linkdyn v1 "));
        assert_eq!(&bytes[124..128], &[0x00, 0x01, b'I', b'M']);
        let mut k = 128;
        let mut count = 0;
        while k < bytes.len() {
            let word =
                |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
            assert_eq!(word(k), MI_MATRIX, "element {count} at byte {k}");
            let n = word(k + 4) as usize;
            assert_eq!(n % 8, 0, "element {count}: {n} bytes");
            k += 8 + n;
            count += 1;
        }
        assert_eq!(k, bytes.len(), "the last element ends the file");
        assert_eq!(count, 6, "t, two columns, provenance, columns, names");
    }
}
