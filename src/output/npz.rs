//! The NPZ result file (`linkdyn run --format npz`): what NumPy's `np.savez` writes, so that
//! `d = np.load("F.npz")` reads it in one line — one float64 array per column (`d["t"]`,
//! `d["coupler.phi"]`, …) and the provenance as a JSON string (`json.loads(str(d["provenance"]))`).
//!
//! Layout: a zip archive of uncompressed (STORED) members `NAME.npy`, each a `.npy` version
//! 1.0 file: the magic `\x93NUMPY`, version bytes 1, 0, a little-endian `u16` header length,
//! the header dict `{'descr': '<f8', 'fortran_order': False, 'shape': (N,), }` padded with
//! spaces and ended by `\n` so that the data starts at a multiple of 64 bytes, then the data
//! (little-endian). The provenance member is a 0-d array of dtype `<U{n}` (UTF-32LE), which
//! `np.load` reads without `allow_pickle`. Member names are UTF-8 (zip flag bit 11); times are
//! the DOS epoch, so the same run gives a byte-identical file. No zip64: an archive of 4 GiB
//! or more is refused ([`check_npz_size`], before the run).
//!
//! Unlike the CSV, the NPZ is written after the run from the columns kept in memory (a
//! member's header needs its length and its CRC-32 before its data).
//!
//! # References
//! 1. NumPy Enhancement Proposal 1, "A simple file format for NumPy arrays" (the `.npy`
//!    format, version 1.0), and `numpy.lib.format`.
//! 2. PKWARE, *APPNOTE.TXT — .ZIP File Format Specification*, version 6.3.10, sections 4.3.7
//!    (local file header), 4.3.12 (central directory header), 4.3.16 (end of central directory
//!    record), 4.4.7 (CRC-32).

use super::{OutputError, io_error};
use crate::simulation::{Columns, Provenance};
use std::io::Write;
use std::path::Path;

/// Name of the member holding the provenance (a JSON string).
pub const PROVENANCE_MEMBER: &str = "provenance";

/// Largest archive this writer makes: zip offsets and sizes are `u32` without zip64.
const MAX_ARCHIVE_BYTES: u64 = u32::MAX as u64;

/// Bytes of the `.npy` header (magic to `\n`): a multiple of 64.
fn npy_header(descr: &str, shape: &str) -> Vec<u8> {
    let dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    // 6 magic + 2 version + 2 length bytes, the dict, the padding and the final newline.
    let unpadded = 10 + dict.len() + 1;
    let padding = (64 - unpadded % 64) % 64;
    let len = dict.len() + padding + 1;
    let mut h = Vec::with_capacity(10 + len);
    h.extend_from_slice(b"\x93NUMPY\x01\x00");
    // The dict of a 1-d float64 array is about 70 bytes: far below u16::MAX.
    h.extend_from_slice(&(len as u16).to_le_bytes());
    h.extend_from_slice(dict.as_bytes());
    h.extend(std::iter::repeat_n(b' ', padding));
    h.push(b'\n');
    h
}

/// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320) as zip uses it, fed piece by piece.
struct Crc32 {
    table: [u32; 256],
    value: u32,
}

impl Crc32 {
    fn new() -> Self {
        let mut table = [0u32; 256];
        for (n, entry) in table.iter_mut().enumerate() {
            let mut c = n as u32;
            for _ in 0..8 {
                c = if c & 1 == 1 {
                    0xEDB8_8320 ^ (c >> 1)
                } else {
                    c >> 1
                };
            }
            *entry = c;
        }
        Crc32 {
            table,
            value: 0xFFFF_FFFF,
        }
    }

    fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.value =
                self.table[((self.value ^ u32::from(b)) & 0xFF) as usize] ^ (self.value >> 8);
        }
    }

    fn finish(&self) -> u32 {
        self.value ^ 0xFFFF_FFFF
    }
}

/// One archive member: its `.npy` header and its data as little-endian bytes, in pieces.
struct Member<'a> {
    name: String,
    header: Vec<u8>,
    data: Data<'a>,
}

enum Data<'a> {
    F64(&'a [f64]),
    Bytes(Vec<u8>),
}

impl Member<'_> {
    fn data_len(&self) -> u64 {
        match &self.data {
            Data::F64(v) => 8 * v.len() as u64,
            Data::Bytes(b) => b.len() as u64,
        }
    }

    fn size(&self) -> u64 {
        self.header.len() as u64 + self.data_len()
    }

    /// Sends the member's bytes (header, then data) to `f` in chunks.
    fn each_chunk(&self, mut f: impl FnMut(&[u8]) -> std::io::Result<()>) -> std::io::Result<()> {
        f(&self.header)?;
        match &self.data {
            Data::Bytes(b) => f(b),
            Data::F64(v) => {
                let mut buf = Vec::with_capacity(8 * 1024);
                for chunk in v.chunks(1024) {
                    buf.clear();
                    for x in chunk {
                        buf.extend_from_slice(&x.to_le_bytes());
                    }
                    f(&buf)?;
                }
                Ok(())
            }
        }
    }
}

/// Bytes of a zip archive of `members` whose names total `name_bytes` and whose `.npy` files
/// total `content` bytes: per member a 30-byte local header and a 46-byte central directory
/// entry, each with the name, and a 22-byte end record.
fn archive_size(members: u64, name_bytes: u64, content: u64) -> u64 {
    members * (30 + 46) + 2 * name_bytes + content + 22
}

/// Member name of a column: the column name with `.npy` (`np.load` strips it again).
fn member_name(column: &str) -> String {
    format!("{column}.npy")
}

/// Checks, before a run, that an NPZ of `samples` samples of `t` and the columns `names` stays
/// below 4 GiB (no zip64) and 65 535 members. `target` names the file in the error.
pub fn check_npz_size(target: &Path, samples: usize, names: &[String]) -> Result<(), OutputError> {
    let members = names.len() as u64 + 2;
    let name_bytes: u64 = names
        .iter()
        .map(|n| member_name(n).len() as u64)
        .sum::<u64>()
        + member_name("t").len() as u64
        + member_name(PROVENANCE_MEMBER).len() as u64;
    // A 128-byte .npy header covers any shape; the provenance is a few kB at most.
    let content = members * 128 + (names.len() as u64 + 1) * 8 * samples as u64 + 65_536;
    let size = archive_size(members, name_bytes, content);
    if members > u64::from(u16::MAX) || size > MAX_ARCHIVE_BYTES {
        return Err(OutputError::Target {
            path: target.display().to_string(),
            reason: format!(
                "an NPZ of {samples} samples × {} columns would take about {:.2} GB; this writer makes archives below 4 GiB (no zip64): use --format csv, or raise --dt",
                names.len() + 1,
                size as f64 / 1e9
            ),
        });
    }
    Ok(())
}

/// Writes the NPZ of a run to `out`: `t`, one member per column of `names` (the columns of
/// `data`, in order) and the provenance as JSON. `path` names the file in errors.
///
/// Errors: [`OutputError::Io`] for a failed write, [`OutputError::Target`] if the archive
/// would reach 4 GiB.
pub fn write_npz<W: Write>(
    out: &mut W,
    path: &Path,
    provenance: &Provenance,
    names: &[String],
    data: &Columns,
) -> Result<(), OutputError> {
    check_npz_size(path, data.t.len(), names)?;
    let provenance_json = serde_json::to_string(provenance).map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        reason: format!("cannot serialise the provenance: {e}"),
    })?;
    let mut members = vec![f64_member("t", &data.t)];
    for (name, column) in names.iter().zip(&data.columns) {
        members.push(f64_member(name, column));
    }
    let chars: Vec<char> = provenance_json.chars().collect();
    members.push(Member {
        name: member_name(PROVENANCE_MEMBER),
        header: npy_header(&format!("<U{}", chars.len()), "()"),
        data: Data::Bytes(
            chars
                .iter()
                .flat_map(|&c| u32::from(c).to_le_bytes())
                .collect(),
        ),
    });
    write_zip(out, &members).map_err(|e| io_error(path, e))
}

/// A float64 member.
fn f64_member<'a>(name: &str, v: &'a [f64]) -> Member<'a> {
    Member {
        name: member_name(name),
        header: npy_header("<f8", &format!("({},)", v.len())),
        data: Data::F64(v),
    }
}

/// Writes `members` as a zip archive of STORED entries.
fn write_zip<W: Write>(out: &mut W, members: &[Member<'_>]) -> std::io::Result<()> {
    // DOS date 1980-01-01 00:00:00: (year − 1980) << 9 | month << 5 | day.
    const DOS_TIME: u16 = 0;
    const DOS_DATE: u16 = (1 << 5) | 1;
    // Bit 11: names are UTF-8.
    const FLAGS: u16 = 1 << 11;
    const VERSION: u16 = 20;
    let mut offset: u32 = 0;
    let mut central = Vec::new();
    for m in members {
        let mut crc = Crc32::new();
        m.each_chunk(|b| {
            crc.update(b);
            Ok(())
        })?;
        let crc = crc.finish();
        // check_npz_size bounded the total below u32::MAX.
        let size = m.size() as u32;
        let name = m.name.as_bytes();
        let name_len = name.len() as u16;
        let mut local = Vec::with_capacity(30 + name.len());
        local.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        for v in [VERSION, FLAGS, 0, DOS_TIME, DOS_DATE] {
            local.extend_from_slice(&v.to_le_bytes());
        }
        for v in [crc, size, size] {
            local.extend_from_slice(&v.to_le_bytes());
        }
        for v in [name_len, 0] {
            local.extend_from_slice(&v.to_le_bytes());
        }
        local.extend_from_slice(name);
        out.write_all(&local)?;
        m.each_chunk(|b| out.write_all(b))?;

        central.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
        for v in [VERSION, VERSION, FLAGS, 0, DOS_TIME, DOS_DATE] {
            central.extend_from_slice(&v.to_le_bytes());
        }
        for v in [crc, size, size] {
            central.extend_from_slice(&v.to_le_bytes());
        }
        // Name length, extra length, comment length, disk number, internal attributes.
        for v in [name_len, 0, 0, 0, 0] {
            central.extend_from_slice(&v.to_le_bytes());
        }
        // External attributes, offset of the local header.
        for v in [0u32, offset] {
            central.extend_from_slice(&v.to_le_bytes());
        }
        central.extend_from_slice(name);
        offset += local.len() as u32 + size;
    }
    let count = members.len() as u16;
    out.write_all(&central)?;
    let mut end = Vec::with_capacity(22);
    end.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
    for v in [0u16, 0, count, count] {
        end.extend_from_slice(&v.to_le_bytes());
    }
    for v in [central.len() as u32, offset] {
        end.extend_from_slice(&v.to_le_bytes());
    }
    end.extend_from_slice(&0u16.to_le_bytes());
    out.write_all(&end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32_matches_the_standard_check_value() {
        // The CRC-32 check value of the ASCII string "123456789" (APPNOTE / ISO 3309).
        let mut c = Crc32::new();
        c.update(b"12345");
        c.update(b"6789");
        assert_eq!(c.finish(), 0xCBF4_3926, "got {:08x}", c.finish());
    }

    #[test]
    fn npy_headers_end_on_a_64_byte_boundary_with_a_newline() {
        for (descr, shape) in [("<f8", "(0,)"), ("<f8", "(4801,)"), ("<U12345", "()")] {
            let h = npy_header(descr, shape);
            assert_eq!(h.len() % 64, 0, "{descr} {shape}: {} bytes", h.len());
            assert_eq!(h.last(), Some(&b'\n'), "{descr} {shape}");
            let declared = u16::from_le_bytes([h[8], h[9]]) as usize;
            assert_eq!(
                declared + 10,
                h.len(),
                "{descr} {shape}: header length field"
            );
        }
    }

    #[test]
    fn archive_members_and_directory_are_consistent() {
        let provenance = Provenance {
            linkdyn_version: "v".into(),
            model: crate::model::ModelSource {
                path: "m.toml".into(),
                sha256: "0".into(),
                overrides: vec![],
            },
            settings: Default::default(),
        };
        let data = Columns {
            t: vec![0.0, 0.5],
            columns: vec![vec![1.0, -2.5e-7]],
            constraint_violation: vec![0.0, 0.0],
            events: vec![],
        };
        let mut bytes = Vec::new();
        let names = vec!["a.x".to_string()];
        let r = write_npz(&mut bytes, Path::new("r.npz"), &provenance, &names, &data);
        assert!(r.is_ok(), "{r:?}");
        // End record: 3 members, directory right after the members.
        let end = &bytes[bytes.len() - 22..];
        assert_eq!(&end[..4], &[0x50, 0x4b, 0x05, 0x06], "end record signature");
        assert_eq!(u16::from_le_bytes([end[10], end[11]]), 3, "members");
        let cd_size = u32::from_le_bytes([end[12], end[13], end[14], end[15]]) as usize;
        let cd_offset = u32::from_le_bytes([end[16], end[17], end[18], end[19]]) as usize;
        assert_eq!(cd_offset + cd_size + 22, bytes.len(), "directory placement");
        // The first member: t.npy, its .npy header (length from the header itself), then
        // 2 × 8 bytes of little-endian data.
        assert_eq!(&bytes[30..35], b"t.npy");
        let header_len = 10 + u16::from_le_bytes([bytes[35 + 8], bytes[35 + 9]]) as usize;
        let data_start = 30 + 5 + header_len;
        assert_eq!(&bytes[data_start..data_start + 8], &0.0f64.to_le_bytes());
        assert_eq!(
            &bytes[data_start + 8..data_start + 16],
            &0.5f64.to_le_bytes()
        );
    }
}
