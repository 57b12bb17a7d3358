//! `linkdyn run --format npz`: the archive holds every CSV column with the same f64 bits, is a
//! valid zip of `.npy` members (checked here without NumPy; the Python tests read it with
//! `np.load`), and a failed run leaves no file, as for the CSV.

mod cli_common;

use cli_common::{linkdyn_stderr, scratch};
use std::path::Path;

fn u16_at(b: &[u8], k: usize) -> usize {
    u16::from_le_bytes([b[k], b[k + 1]]) as usize
}

fn u32_at(b: &[u8], k: usize) -> usize {
    u32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]) as usize
}

/// The members of a zip of STORED entries: (name, content), walking the local headers.
fn members(bytes: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut k = 0;
    while u32_at(bytes, k) == 0x0403_4b50 {
        assert_eq!(u16_at(bytes, k + 8), 0, "member {} is STORED", out.len());
        let size = u32_at(bytes, k + 18);
        assert_eq!(size, u32_at(bytes, k + 22), "stored: sizes equal");
        let (name_len, extra_len) = (u16_at(bytes, k + 26), u16_at(bytes, k + 28));
        let name = String::from_utf8_lossy(&bytes[k + 30..k + 30 + name_len]).into_owned();
        let start = k + 30 + name_len + extra_len;
        out.push((name, bytes[start..start + size].to_vec()));
        k = start + size;
    }
    assert_eq!(
        u32_at(bytes, k),
        0x0201_4b50,
        "central directory follows the members"
    );
    out
}

/// The f64 data of a 1-d `<f8` .npy file.
fn npy_f64(npy: &[u8]) -> Vec<f64> {
    assert_eq!(&npy[..8], b"\x93NUMPY\x01\x00", "npy v1.0 magic");
    let data = 10 + u16_at(npy, 8);
    assert_eq!(data % 64, 0, "data aligned to 64 bytes");
    let header = String::from_utf8_lossy(&npy[10..data]);
    assert!(header.contains("'descr': '<f8'"), "{header}");
    npy[data..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
        .collect()
}

#[test]
fn npz_holds_the_csv_columns_bit_for_bit() {
    let dir = scratch("columns");
    let (csv, npz) = (dir.join("a.csv"), dir.join("b.npz"));
    let common = ["run", "models/farahan2016.toml", "--revs", "0.25", "--out"];
    let (code, err) = linkdyn_stderr(&[&common[..], &[&csv.display().to_string()]].concat());
    assert_eq!(code, 0, "{err}");
    let npz_arg = npz.display().to_string();
    let (code, err) =
        linkdyn_stderr(&[&common[..], &[npz_arg.as_str(), "--format", "npz"]].concat());
    assert_eq!(code, 0, "{err}");

    let text = std::fs::read_to_string(&csv).unwrap_or_default();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let bytes = std::fs::read(&npz).unwrap_or_default();
    let members = members(&bytes);
    let names: Vec<&str> = members.iter().map(|(n, _)| n.as_str()).collect();
    let mut expected: Vec<String> = header.iter().map(|h| format!("{h}.npy")).collect();
    expected.push("provenance.npy".into());
    assert_eq!(
        names, expected,
        "one member per column, then the provenance"
    );
    for (k, (name, content)) in members.iter().take(header.len()).enumerate() {
        let values = npy_f64(content);
        assert_eq!(values.len(), rows.len(), "{name}: samples");
        for (i, (v, row)) in values.iter().zip(&rows).enumerate() {
            assert_eq!(
                v.to_bits(),
                row[k].to_bits(),
                "{name}[{i}]: npz {v} vs csv {}",
                row[k]
            );
        }
    }
    // The summary goes beside the archive, as beside a CSV.
    assert!(dir.join("b.json").exists(), "summary b.json");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_failed_npz_run_leaves_nothing() {
    let dir = scratch("failed");
    let npz = dir.join("r.npz");
    let (code, err) = linkdyn_stderr(&[
        "run",
        "models/farahan2016.toml",
        "--max-steps",
        "10",
        "--format",
        "npz",
        "--out",
        &npz.display().to_string(),
    ]);
    assert_eq!(code, 3, "solver failure exit code: {err}");
    let left: Vec<_> = std::fs::read_dir(&dir)
        .map(|r| r.filter_map(|e| e.ok()).map(|e| e.file_name()).collect())
        .unwrap_or_default();
    assert!(left.is_empty(), "left behind: {left:?}");
    let _ = std::fs::remove_dir_all(Path::new(&dir));
}
