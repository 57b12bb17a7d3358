//! `linkdyn run --format mat`: the file is a MATLAB Level-5 MAT-file as The MathWorks
//! documents it (read here by a parser written from the format description, not from the
//! writer; python/tests/test_mat.py reads it with `scipy.io.loadmat`), every variable holds
//! its CSV column with the same f64 bits under the documented MATLAB name, names that would
//! meet in one MATLAB name are refused before any work, and a failed run leaves no file.

mod cli_common;

use cli_common::{linkdyn, scratch};
use std::path::Path;

fn u16_at(b: &[u8], k: usize) -> u16 {
    u16::from_le_bytes([b[k], b[k + 1]])
}

fn u32_at(b: &[u8], k: usize) -> u32 {
    u32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]])
}

/// One data element: its type and its data (without the padding).
struct Element<'a> {
    ty: u32,
    data: &'a [u8],
}

/// Reads the data element at `k`; returns it and the offset of the next one. Handles both
/// tag forms of the format: the small one (type and length as two u16, up to 4 data bytes in
/// the tag) and the normal one (type and length as two u32, data padded to 8 bytes).
fn element(b: &[u8], k: usize) -> (Element<'_>, usize) {
    let first = u32_at(b, k);
    if first >> 16 != 0 {
        let (ty, n) = (u32::from(u16_at(b, k)), u16_at(b, k + 2) as usize);
        assert!(n <= 4, "small element at {k}: {n} bytes");
        return (
            Element {
                ty,
                data: &b[k + 4..k + 4 + n],
            },
            k + 8,
        );
    }
    let n = u32_at(b, k + 4) as usize;
    let data = &b[k + 8..k + 8 + n];
    (Element { ty: first, data }, k + 8 + n.div_ceil(8) * 8)
}

/// A variable of the file.
struct Variable {
    name: String,
    class: u32,
    dims: Vec<i32>,
    /// The real part's data type and bytes.
    ty: u32,
    real: Vec<u8>,
}

impl Variable {
    fn doubles(&self) -> Vec<f64> {
        assert_eq!(
            (self.class, self.ty),
            (6, 9),
            "{}: mxDOUBLE / miDOUBLE",
            self.name
        );
        self.real
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
            .collect()
    }

    /// The rows of a char matrix (column-major UTF-16 code units), trailing spaces removed.
    fn rows(&self) -> Vec<String> {
        assert_eq!(
            (self.class, self.ty),
            (4, 4),
            "{}: mxCHAR / miUINT16",
            self.name
        );
        let units: Vec<u16> = self
            .real
            .chunks_exact(2)
            .map(|c| u16::from_le_bytes([c[0], c[1]]))
            .collect();
        let (rows, cols) = (self.dims[0] as usize, self.dims[1] as usize);
        assert_eq!(units.len(), rows * cols, "{}: size", self.name);
        (0..rows)
            .map(|r| {
                let row: Vec<u16> = (0..cols).map(|c| units[c * rows + r]).collect();
                String::from_utf16_lossy(&row).trim_end().to_string()
            })
            .collect()
    }
}

/// Parses a whole Level-5 MAT-file of uncompressed numeric and char arrays, checking the
/// header and every tag on the way.
fn parse(bytes: &[u8]) -> Vec<Variable> {
    assert!(bytes.len() >= 128, "header: {} bytes", bytes.len());
    let text = String::from_utf8_lossy(&bytes[..116]);
    assert!(
        text.starts_with("MATLAB 5.0 MAT-file"),
        "header text: {text}"
    );
    assert!(
        bytes[116..124].iter().all(|&b| b == 0 || b == b' '),
        "no subsystem data"
    );
    assert_eq!(u16_at(bytes, 124), 0x0100, "version");
    assert_eq!(&bytes[126..128], b"IM", "little-endian indicator");
    let mut out = Vec::new();
    let mut k = 128;
    while k < bytes.len() {
        assert_eq!(k % 8, 0, "element at {k} aligned to 8 bytes");
        let (matrix, next) = element(bytes, k);
        assert_eq!(matrix.ty, 14, "miMATRIX at {k}");
        assert_eq!(matrix.data.len() % 8, 0, "miMATRIX at {k} ends aligned");
        let m = matrix.data;
        let (flags, j) = element(m, 0);
        assert_eq!(
            (flags.ty, flags.data.len()),
            (6, 8),
            "array flags: miUINT32 × 2"
        );
        let flag_word = u32_at(flags.data, 0);
        assert_eq!(flag_word & 0xFF00, 0, "not complex, global or logical");
        let (dims, j) = element(m, j);
        assert_eq!(dims.ty, 5, "dimensions: miINT32");
        let dims: Vec<i32> = dims
            .data
            .chunks_exact(4)
            .map(|c| i32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        assert!(dims.len() >= 2, "at least two dimensions");
        let (name, j) = element(m, j);
        assert_eq!(name.ty, 1, "array name: miINT8");
        let name = String::from_utf8_lossy(name.data).into_owned();
        let (real, j) = element(m, j);
        assert_eq!(j, m.len(), "{name}: the real part ends the element");
        out.push(Variable {
            name,
            class: flag_word & 0xFF,
            dims,
            ty: real.ty,
            real: real.data.to_vec(),
        });
        k = next;
    }
    assert_eq!(k, bytes.len(), "the last element ends the file");
    out
}

/// The columns of a result CSV: (header, rows).
type Csv = (Vec<String>, Vec<Vec<f64>>);

/// Reads a result CSV.
fn read_csv(csv: &Path) -> Csv {
    let text = std::fs::read_to_string(csv).unwrap_or_default();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines
        .next()
        .unwrap_or_default()
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    (header, rows)
}

/// Whether `name` is a valid MATLAB variable name (`isvarname`, keywords aside).
fn is_varname(name: &str) -> bool {
    name.len() <= 63
        && name.starts_with(|c: char| c.is_ascii_alphabetic())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Runs `linkdyn run MODEL ARGS… --out OUT` twice, as CSV and as MAT; returns the CSV and the
/// parsed MAT-file's variables.
fn csv_and_mat(dir: &Path, model: &str, args: &[&str]) -> (Csv, Vec<Variable>) {
    let (csv, mat) = (dir.join("a.csv"), dir.join("b.mat"));
    let (csv_arg, mat_arg) = (csv.display().to_string(), mat.display().to_string());
    let common = [&["run", model], args].concat();
    let (code, _, err) = linkdyn(&[&common[..], &["--out", &csv_arg]].concat());
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = linkdyn(&[&common[..], &["--out", &mat_arg, "--format", "mat"]].concat());
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(&mat).unwrap_or_default();
    (read_csv(&csv), parse(&bytes))
}

#[test]
fn mat_holds_the_csv_columns_bit_for_bit_under_matlab_names() {
    let dir = scratch("columns");
    let ((header, rows), vars) = csv_and_mat(&dir, "models/farahan2016.toml", &["--revs", "0.25"]);
    let names: Vec<&str> = vars.iter().map(|v| v.name.as_str()).collect();
    // farahan2016's names have no '-' and start with a letter: the rule is dots to '_'.
    let mut expected: Vec<String> = header.iter().map(|h| h.replace('.', "_")).collect();
    expected.extend(["provenance", "columns", "names"].map(String::from));
    assert_eq!(
        names, expected,
        "t, one variable per column, then the three fixed ones"
    );
    assert!(names.contains(&"coupler_phi"), "{names:?}");
    for (k, var) in vars.iter().take(header.len()).enumerate() {
        assert!(is_varname(&var.name), "{} is a MATLAB name", var.name);
        assert_eq!(
            var.dims,
            [rows.len() as i32, 1],
            "{}: a column vector",
            var.name
        );
        let values = var.doubles();
        for (i, (v, row)) in values.iter().zip(&rows).enumerate() {
            assert_eq!(
                v.to_bits(),
                row[k].to_bits(),
                "{}[{i}]: mat {v} vs csv {}",
                var.name,
                row[k]
            );
        }
    }
    let fixed = &vars[header.len()..];
    // The names map back: row k of `columns` is the CSV's k-th header, of `names` the variable.
    assert_eq!(fixed[1].rows(), header, "columns: linkdyn's names, t first");
    assert_eq!(
        fixed[2].rows(),
        &expected[..header.len()],
        "names: the MATLAB names in the same rows"
    );
    // The provenance is the summary's, as JSON text in a 1 × L char array.
    assert_eq!(fixed[0].dims[0], 1, "provenance: one row");
    let text = fixed[0].rows().concat();
    let provenance: serde_json::Value =
        serde_json::from_str(&text).unwrap_or_else(|e| panic!("provenance {text}: {e}"));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("b.json")).unwrap_or_default())
            .unwrap_or_else(|e| panic!("b.json: {e}"));
    assert_eq!(
        provenance, summary["provenance"],
        "provenance = the summary's"
    );
    assert!(
        dir.join("b.impacts.csv").exists(),
        "impact log b.impacts.csv"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The pendulum with output points of the given names, written into `dir`.
fn pendulum_with_outputs(dir: &Path, outputs: &[&str]) -> String {
    let mut text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("models/pendulum.toml"))
            .unwrap_or_default();
    for name in outputs {
        text.push_str(&format!(
            "\n[[outputs]]\nname = \"{name}\"\nbody = \"rod\"\nlocal = [0.5, 0.0]\n"
        ));
    }
    let path = dir.join("pendulum.toml");
    std::fs::write(&path, text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    path.display().to_string()
}

#[test]
fn dashes_and_leading_digits_map_to_documented_names() {
    let dir = scratch("mapping");
    let model = pendulum_with_outputs(&dir, &["tip-1", "2nd"]);
    let ((header, rows), vars) = csv_and_mat(&dir, &model, &["--t-end", "0.01", "--dt", "1e-3"]);
    let by_name = |n: &str| {
        vars.iter()
            .position(|v| v.name == n)
            .unwrap_or_else(|| panic!("no variable {n}"))
    };
    for (column, name) in [
        ("rod.phi", "rod_phi"),
        ("tip-1.x", "tip_1_x"),
        ("tip-1.vy", "tip_1_vy"),
        ("2nd.x", "x2nd_x"),
        ("2nd.ay", "x2nd_ay"),
    ] {
        let k = header
            .iter()
            .position(|h| h == column)
            .unwrap_or_else(|| panic!("no column {column} in {header:?}"));
        let v = by_name(name);
        assert_eq!(v, k, "{column} is variable {name} at the same place");
        let values = vars[v].doubles();
        assert!(
            values
                .iter()
                .zip(&rows)
                .all(|(a, row)| a.to_bits() == row[k].to_bits()),
            "{name} holds {column}"
        );
        // The two char matrices pair them in the same row.
        let columns = vars[by_name("columns")].rows();
        let names = vars[by_name("names")].rows();
        assert_eq!((columns[k].as_str(), names[k].as_str()), (column, name));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The files in `dir` other than the model.
fn left(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n != "pendulum.toml")
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

#[test]
fn names_that_meet_in_one_matlab_name_are_refused_before_any_work() {
    let dir = scratch("collision");
    let mat = dir.join("r.mat").display().to_string();
    let model = pendulum_with_outputs(&dir, &["tip-1", "tip_1"]);
    let (code, _, err) = linkdyn(&[
        "run", &model, "--t-end", "0.01", "--format", "mat", "--out", &mat,
    ]);
    assert_eq!(code, 2, "bad input: {err}");
    assert!(
        err.contains("column tip_1.x and column tip-1.x would both be the MATLAB variable tip_1_x"),
        "{err}"
    );
    assert!(
        err.contains("--format csv or npz"),
        "says what works: {err}"
    );
    assert_eq!(left(&dir), Vec::<String>::new(), "nothing written");
    // A name past MATLAB's 63 characters: refused too (MATLAB would cut it on load).
    let long = "p".repeat(62);
    let model = pendulum_with_outputs(&dir, &[long.as_str()]);
    let (code, _, err) = linkdyn(&[
        "run", &model, "--t-end", "0.01", "--format", "mat", "--out", &mat,
    ]);
    assert_eq!(code, 2, "bad input: {err}");
    assert!(
        err.contains(&format!(
            "column {long}.x would be the MATLAB variable {long}_x of 64 characters"
        )),
        "{err}"
    );
    assert_eq!(left(&dir), Vec::<String>::new(), "nothing written");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failed_mat_run_leaves_no_file_and_keeps_the_earlier_one() {
    let dir = scratch("failed");
    let mat = dir.join("r.mat");
    let mat_arg = mat.display().to_string();
    let run = |extra: &[&str]| {
        linkdyn(
            &[
                &[
                    "run",
                    "models/farahan2016.toml",
                    "--format",
                    "mat",
                    "--out",
                    &mat_arg,
                ][..],
                extra,
            ]
            .concat(),
        )
    };
    let (code, _, err) = run(&["--max-steps", "10"]);
    assert_eq!(code, 3, "solver failure exit code: {err}");
    assert_eq!(left(&dir), Vec::<String>::new(), "left behind");
    let (code, _, err) = run(&["--revs", "0.05"]);
    assert_eq!(code, 0, "{err}");
    let before = std::fs::read(&mat).unwrap_or_default();
    assert!(!parse(&before).is_empty());
    let (code, _, err) = run(&["--max-steps", "10"]);
    assert_eq!(code, 3, "solver failure exit code: {err}");
    assert_eq!(
        left(&dir),
        ["r.impacts.csv", "r.json", "r.mat"],
        "the earlier files, no temporary or lock file"
    );
    assert_eq!(
        std::fs::read(&mat).unwrap_or_default(),
        before,
        "r.mat untouched"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
