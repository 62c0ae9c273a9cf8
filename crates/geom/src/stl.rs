//! STL, binary and ASCII: bytes in, triangles or a [`Mesh`] out.
//!
//! A binary file is recognised by its size (84 bytes plus 50 a triangle, as
//! its header count says); a file that does not fit and begins with `solid`
//! (and has no NUL byte) is read as ASCII. Facet normals are ignored: the
//! corners say which way a triangle faces, and drop-cutter does not care.

use std::io::{BufReader, Read, Write};

use crate::error::{Error, ErrorKind};
use crate::mesh::{Mesh, Triangle, Vec3};

/// The triangles of an STL file, binary or ASCII, in file order (degenerate
/// ones included). Fails on a truncated or mis-sized file, an unreadable
/// ASCII line, or a coordinate that is not a number the format can hold
/// (a 32-bit float: NaN, infinite or beyond ±3.4e38).
pub fn parse_stl(bytes: &[u8]) -> Result<Vec<Triangle>, Error> {
    read_stl(bytes).map(|f| f.triangles)
}

/// An STL file read: its triangles, and what a reader should be told.
#[derive(Debug, Clone, PartialEq)]
pub struct StlFile {
    /// The triangles in file order (degenerate ones included).
    pub triangles: Vec<Triangle>,
    /// An ASCII file that ends (after whole facets) without its `endsolid`
    /// line: it may be cut short. The number of its last line.
    pub cut_short: Option<usize>,
}

/// Reads an STL file as [`parse_stl`], saying too whether an ASCII file
/// lacks its `endsolid` line.
pub fn read_stl(bytes: &[u8]) -> Result<StlFile, Error> {
    let binary_size = |n: u32| 84 + 50 * u64::from(n);
    let count = bytes.get(80..84).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    if let Some(n) = count {
        if binary_size(n) == bytes.len() as u64 {
            return Ok(StlFile { triangles: parse_binary(&bytes[84..], n as usize)?, cut_short: None });
        }
    }
    if looks_ascii(bytes) {
        return parse_ascii(bytes);
    }
    let found = bytes.len() as u64;
    match count {
        None => Err(stl_error(format!("truncated STL: {found} bytes, shorter than the 84-byte binary header"))),
        Some(n) if binary_size(n) > found => Err(stl_error(format!(
            "truncated binary STL: the header announces {n} triangles ({} bytes), the file has {found} bytes",
            binary_size(n)
        ))),
        Some(n) => Err(stl_error(format!(
            "binary STL of the wrong size: the header announces {n} triangles ({} bytes), the file has {found} bytes",
            binary_size(n)
        ))),
    }
}

impl Mesh {
    /// Reads an STL file (see [`parse_stl`]) into a mesh, skipping
    /// degenerate triangles; a mesh with no triangle left is an error.
    pub fn from_stl(bytes: &[u8]) -> Result<Mesh, Error> {
        Mesh::from_stl_triangles(parse_stl(bytes)?)
    }

    /// The mesh of an STL's `triangles` (see [`Mesh::from_stl`]).
    pub fn from_stl_triangles(triangles: Vec<Triangle>) -> Result<Mesh, Error> {
        Mesh::from_mesh_checked(Mesh::from_triangles(triangles))
    }

    /// `mesh`, or the error of an STL with no triangle left.
    fn from_mesh_checked(mesh: Mesh) -> Result<Mesh, Error> {
        if mesh.is_empty() {
            return Err(stl_error(match mesh.skipped() {
                0 => "empty STL: no triangles".to_string(),
                skipped => format!("empty STL: all {skipped} triangles are degenerate (zero area)"),
            }));
        }
        Ok(mesh)
    }
}

/// Bytes that are not an STL mesh.
fn stl_error(message: String) -> Error {
    Error::new(ErrorKind::Stl, message)
}

/// Triangle `triangle` (from 1) with a NaN or infinite coordinate.
fn non_finite(triangle: usize) -> Error {
    stl_error(format!("STL triangle {triangle} has a NaN or infinite coordinate"))
}

fn looks_ascii(bytes: &[u8]) -> bool {
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    let head = &bytes[start..];
    head.len() >= 5 && head[..5].eq_ignore_ascii_case(b"solid") && !bytes.contains(&0)
}

fn parse_binary(body: &[u8], n: usize) -> Result<Vec<Triangle>, Error> {
    let mut out = Vec::with_capacity(n);
    for (k, rec) in body.chunks_exact(50).enumerate() {
        out.push(record(rec).ok_or_else(|| non_finite(k + 1))?);
    }
    Ok(out)
}

/// The triangle of a binary STL's 50-byte record; `None` where a
/// coordinate is NaN or infinite.
fn record(rec: &[u8]) -> Option<Triangle> {
    let f = |i: usize| {
        let b = &rec[12 + 4 * i..16 + 4 * i];
        f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let p = |c: usize| Vec3::new(f(3 * c), f(3 * c + 1), f(3 * c + 2));
    let t = Triangle::new(p(0), p(1), p(2));
    t.v.iter().all(|v| v.is_finite()).then_some(t)
}

/// Reads the `count` triangles of a binary STL from `body` (the bytes after
/// its 84-byte header) straight into a mesh, each corner multiplied by
/// `scale`: the same mesh and errors as [`Mesh::from_stl`] of the whole
/// file (scaled), without the file or its triangles ever held whole (a
/// megabyte is read at a time; the mesh keeps each distinct corner once).
pub fn read_binary_stl_mesh(body: impl Read, count: u32, scale: f64) -> Result<Mesh, Error> {
    let mut reader = BufReader::with_capacity(1 << 20, body);
    let mut failed = None;
    let mut rec = [0u8; 50];
    let triangles = (0..count as usize).map_while(|k| {
        if let Err(e) = reader.read_exact(&mut rec) {
            failed = Some(stl_error(format!("cannot read STL triangle {}: {e}", k + 1)));
            return None;
        }
        match record(&rec) {
            Some(t) if scale == 1.0 => Some(t),
            Some(t) => Some(Triangle { v: t.v.map(|p| p * scale) }),
            None => {
                failed = Some(non_finite(k + 1));
                None
            }
        }
    });
    let mesh = Mesh::from_triangles_counted(triangles, count as usize);
    match failed {
        Some(e) => Err(e),
        None => Mesh::from_mesh_checked(mesh),
    }
}

fn parse_ascii(bytes: &[u8]) -> Result<StlFile, Error> {
    let text = String::from_utf8_lossy(bytes);
    let mut out = Vec::new();
    let mut corners: Vec<Vec3> = Vec::with_capacity(3);
    let mut in_facet = false;
    let mut last = 0;
    let mut ended = false;
    for (k, line) in text.lines().enumerate() {
        let line_no = k + 1;
        last = line_no;
        let mut words = line.split_whitespace();
        // The column (from 1) of `word`, a slice of `line`.
        let column = |word: &str| line[..word.as_ptr() as usize - line.as_ptr() as usize].chars().count() + 1;
        let first = line.split_whitespace().next().map_or(1, column);
        let at = |message: String, column: usize| Error { at: Some((line_no, column)), ..stl_error(message) };
        let syntax = |message: String| at(message, first);
        match words.next().map(|w| w.to_ascii_lowercase()).as_deref() {
            Some("facet") => {
                if in_facet {
                    return Err(syntax("'facet' inside a facet (missing 'endfacet')".into()));
                }
                in_facet = true;
                corners.clear();
            }
            Some("vertex") => {
                if !in_facet {
                    return Err(syntax("'vertex' outside a facet".into()));
                }
                let mut xyz = [0.0f64; 3];
                for v in &mut xyz {
                    let w = words.next().ok_or_else(|| syntax("'vertex' needs three coordinates".into()))?;
                    let not_a_number = || at(format!("'{w}' is not a number"), column(w));
                    *v = w.parse().map_err(|_| not_a_number())?;
                    if v.is_nan() {
                        return Err(not_a_number());
                    }
                    // The format's numbers are 32-bit floats.
                    if v.abs() > f64::from(f32::MAX) {
                        return Err(at(
                            format!("'{w}' is beyond the range of an STL coordinate (a 32-bit float, ±3.4e38)"),
                            column(w),
                        ));
                    }
                }
                if corners.len() == 3 {
                    return Err(syntax("a facet with more than three vertices".into()));
                }
                if !xyz.iter().all(|v| v.is_finite()) {
                    return Err(non_finite(out.len() + 1));
                }
                corners.push(Vec3::new(xyz[0], xyz[1], xyz[2]));
            }
            Some("endfacet") => {
                if !in_facet || corners.len() != 3 {
                    return Err(syntax(format!("a facet with {} vertices, not 3", corners.len())));
                }
                out.push(Triangle::new(corners[0], corners[1], corners[2]));
                in_facet = false;
            }
            Some("endsolid") => ended = true,
            // solid, outer loop, endloop, blank lines.
            _ => {}
        }
    }
    if in_facet {
        return Err(stl_error(format!("truncated ASCII STL: the file ends inside a facet (line {last})")));
    }
    Ok(StlFile { triangles: out, cut_short: (!ended).then_some(last) })
}

/// A binary STL of `triangles` (an 80-byte header of spaces; normals from
/// the corners; coordinates rounded to `f32`, as the format stores them).
pub fn write_binary_stl(triangles: &[Triangle]) -> Vec<u8> {
    let mut out = Vec::with_capacity(84 + 50 * triangles.len());
    write_binary_stl_to(&mut out, triangles.iter().copied()).expect("a Vec takes every byte");
    out
}

/// Writes the binary STL of `triangles` to `out` as they come, one at a
/// time (the same bytes as [`write_binary_stl`]): a surface of a hundred
/// million triangles needs no more memory than one. More than `u32::MAX`
/// triangles, which the format cannot count, is an `InvalidInput` error
/// before anything is written.
pub fn write_binary_stl_to<W: Write + ?Sized>(
    out: &mut W,
    triangles: impl ExactSizeIterator<Item = Triangle>,
) -> std::io::Result<()> {
    let count = u32::try_from(triangles.len()).map_err(|_| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{} triangles: a binary STL holds at most {}", triangles.len(), u32::MAX),
        )
    })?;
    out.write_all(&[b' '; 80])?;
    out.write_all(&count.to_le_bytes())?;
    let mut record = [0u8; 50];
    for t in triangles {
        let n = t.normal();
        let len = n.norm();
        let n = if len > 0.0 { n * (1.0 / len) } else { n };
        for (k, p) in [n, t.v[0], t.v[1], t.v[2]].into_iter().enumerate() {
            for (c, v) in [p.x, p.y, p.z].into_iter().enumerate() {
                let at = 12 * k + 4 * c;
                record[at..at + 4].copy_from_slice(&(v as f32).to_le_bytes());
            }
        }
        out.write_all(&record)?;
    }
    Ok(())
}

/// An ASCII STL of `triangles` (full `f64` precision).
pub fn write_ascii_stl(name: &str, triangles: &[Triangle]) -> String {
    let mut s = format!("solid {name}\n");
    for t in triangles {
        let n = t.normal();
        s += &format!("  facet normal {} {} {}\n    outer loop\n", n.x, n.y, n.z);
        for p in t.v {
            s += &format!("      vertex {} {} {}\n", p.x, p.y, p.z);
        }
        s += "    endloop\n  endfacet\n";
    }
    s + &format!("endsolid {name}\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<Triangle> {
        let p = Vec3::new;
        vec![
            Triangle::new(p(0., 0., 1.), p(2., 0., 1.), p(2., 2., 1.5)),
            Triangle::new(p(0., 0., 1.), p(2., 2., 1.5), p(0., 2., 1.)),
        ]
    }

    #[test]
    fn binary_and_ascii_round_trip() {
        let b = write_binary_stl(&square());
        assert_eq!(b.len(), 84 + 100);
        assert_eq!(parse_stl(&b).unwrap(), square());
        let a = write_ascii_stl("sq", &square());
        assert_eq!(parse_stl(a.as_bytes()).unwrap(), square());
        let m = Mesh::from_stl(a.as_bytes()).unwrap();
        assert_eq!((m.len(), m.vertices().len(), m.edges().len()), (2, 4, 5));
        // A binary file whose header starts with "solid" is still binary.
        let mut b2 = b.clone();
        b2[..5].copy_from_slice(b"solid");
        assert_eq!(parse_stl(&b2).unwrap(), square());
    }

    #[test]
    fn a_binary_file_read_in_pieces_gives_the_same_mesh() {
        // The square, a degenerate triangle (skipped and counted) and the
        // square again (its corners merge with the first's).
        let p = Vec3::new;
        let mut triangles = square();
        triangles.push(Triangle::new(p(0., 0., 0.), p(1., 0., 0.), p(2., 0., 0.)));
        triangles.extend(square());
        let b = write_binary_stl(&triangles);
        let read = read_binary_stl_mesh(&b[84..], triangles.len() as u32, 1.0).unwrap();
        assert_eq!(read, Mesh::from_stl(&b).unwrap());
        assert_eq!((read.len(), read.vertices().len(), read.skipped()), (4, 4, 1));
        // Inches: every corner times 25.4, as the triangles scaled first.
        let inch = read_binary_stl_mesh(&b[84..], triangles.len() as u32, 25.4).unwrap();
        let scaled = triangles.iter().map(|t| Triangle { v: t.v.map(|c| c * 25.4) });
        assert_eq!(inch, Mesh::from_stl_triangles(scaled.collect()).unwrap());
        assert_eq!(inch.vertices()[2], p(50.8, 50.8, 1.5 * 25.4));
        // A NaN in the third triangle: its number, as the whole-file reader says.
        let mut bad = b.clone();
        bad[84 + 2 * 50 + 12..84 + 2 * 50 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = read_binary_stl_mesh(&bad[84..], triangles.len() as u32, 1.0).unwrap_err();
        assert_eq!(e.to_string(), Mesh::from_stl(&bad).unwrap_err().to_string());
        assert!(e.to_string().contains("triangle 3"), "{e}");
        // Cut short: the record that is missing is named.
        let e = read_binary_stl_mesh(&b[84..84 + 120], triangles.len() as u32, 1.0).unwrap_err();
        assert!(e.to_string().contains("cannot read STL triangle 3"), "{e}");
        // Only degenerate triangles: the empty-STL error.
        let flat = write_binary_stl(&triangles[2..3]);
        let e = read_binary_stl_mesh(&flat[84..], 1, 1.0).unwrap_err();
        assert!(e.to_string().contains("all 1 triangles are degenerate"), "{e}");
    }

    #[test]
    fn bad_files_say_what_is_wrong() {
        let b = write_binary_stl(&square());
        let err = |bytes: &[u8]| parse_stl(bytes).unwrap_err().to_string();
        assert_eq!(err(&b[..40]), "truncated STL: 40 bytes, shorter than the 84-byte binary header");
        assert_eq!(
            err(&b[..150]),
            "truncated binary STL: the header announces 2 triangles (184 bytes), the file has 150 bytes"
        );
        let mut long = b.clone();
        long.extend_from_slice(&[0; 7]);
        assert_eq!(
            err(&long),
            "binary STL of the wrong size: the header announces 2 triangles (184 bytes), the file has 191 bytes"
        );
        let mut nan = b.clone();
        nan[84 + 50 + 12 + 4..84 + 50 + 12 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
        assert_eq!(err(&nan), "STL triangle 2 has a NaN or infinite coordinate");
        let a = write_ascii_stl("sq", &square());
        assert_eq!(
            err(a.replacen("vertex 2 2 1.5", "vertex 2 nan 1.5", 1).as_bytes()),
            "line 6, column 16: 'nan' is not a number"
        );
        assert_eq!(
            err(a.replacen("vertex 2 0 1", "vertex 2 x 1", 1).as_bytes()),
            "line 5, column 16: 'x' is not a number"
        );
        assert_eq!(
            err(a.replacen("vertex 2 0 1", "vertex 2 1e39 1", 1).as_bytes()),
            "line 5, column 16: '1e39' is beyond the range of an STL coordinate (a 32-bit float, ±3.4e38)"
        );
        assert_eq!(
            err(a.replacen("vertex 2 0 1", "vertex 2 -1e400 1", 1).as_bytes()),
            "line 5, column 16: '-1e400' is beyond the range of an STL coordinate (a 32-bit float, ±3.4e38)"
        );
        assert_eq!(read_stl(a.as_bytes()).unwrap().cut_short, None);
        let no_end = a.replace("endsolid sq\n", "");
        assert_eq!(read_stl(no_end.as_bytes()).unwrap().cut_short, Some(15));
        assert_eq!(read_stl(&b).unwrap().cut_short, None);
        let cut: String = a.lines().take(12).collect::<Vec<_>>().join("\n");
        assert_eq!(err(cut.as_bytes()), "truncated ASCII STL: the file ends inside a facet (line 12)");
        assert_eq!(
            Mesh::from_stl(b"solid empty\nendsolid empty\n").unwrap_err().to_string(),
            "empty STL: no triangles"
        );
        let flat = [Triangle::new(Vec3::new(0., 0., 0.), Vec3::new(1., 1., 1.), Vec3::new(2., 2., 2.))];
        assert_eq!(
            Mesh::from_stl(&write_binary_stl(&flat)).unwrap_err().to_string(),
            "empty STL: all 1 triangles are degenerate (zero area)"
        );
    }
}
