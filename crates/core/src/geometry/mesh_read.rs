//! Reading triangle meshes from STL (binary and ASCII), OBJ and PLY files, as a stream of
//! triangles that can be walked several times (the fit in [`super::mesh_fit`] makes three passes).
//!
//! OBJ parsing is the maintained crate's (`tobj`); PLY is streamed by `mesh_ply`
//! (faces read a block at a time on each pass, a binary file's vertices read from disk as
//! a block names them: `ply-rs-bw` held 37 times the file). STL is read here, in a
//! few dozen lines, because `stl_io` decided binary or ASCII by its own rule, which disagreed
//! with the files people write and with our length check: a first line of just `solid` (or with
//! CRLF) was read as binary ("failed to fill whole buffer"), a binary STL whose header starts
//! with "solid" as ASCII ("EOF while expecting facet"), `SOLID` in capitals as a damaged binary,
//! a file of two solids only to its first `endsolid`, and an unused `facet normal nan nan nan`
//! failed the triangle. One rule now decides, in [`MeshSource::open`]: a file whose length is
//! exactly a binary STL's for the count in its header is binary, whatever its header says;
//! otherwise one whose first word is `solid` (any case) and whose first kilobyte is text is
//! ASCII, read as a stream of words in any case with any line ends, every solid in the file,
//! normals skipped unread; anything else is a damaged binary STL, named as such.
//!
//! A binary STL is streamed from disk on every pass, never held (so a 10⁷-triangle file costs
//! the same memory as a small one), its length checked against its triangle count before the
//! first pass (a truncated file is named as such, not as a parse error deep inside), and every
//! triangle's coordinates checked finite, naming the triangle. OBJ files are held in memory as
//! the crate loads them; a PLY file's vertices are held and its faces streamed. The input must be a regular file: a FIFO
//! cannot be read twice and a device such as /dev/zero never ends.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use glam::DVec3;
use thiserror::Error;

use super::mesh_ply::{PlyError, PlyStream};

/// A mesh file's format, from its extension (or its first bytes for STL).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    /// STL, binary or ASCII.
    Stl,
    /// Wavefront OBJ (polygons are triangulated).
    Obj,
    /// PLY, ASCII or binary, with `vertex` x, y, z and `face` vertex_indices (or vertex_index).
    Ply,
    /// A surface rollphase made itself (a fitted body offset by a coat), held in memory.
    Made,
}

impl std::fmt::Display for MeshFormat {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            MeshFormat::Stl => "STL",
            MeshFormat::Obj => "OBJ",
            MeshFormat::Ply => "PLY",
            MeshFormat::Made => "made",
        })
    }
}

/// Why a mesh could not be read or fitted; each message names the file and, where there is one,
/// the place (triangle number, direction about the centroid).
#[derive(Debug, Error)]
pub enum MeshError {
    /// The file could not be opened or read.
    #[error("cannot read mesh {}: {reason}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's or the parser's reason.
        reason: String,
    },
    /// Not a regular file.
    #[error(
        "{} is not a regular file (a device, FIFO or folder); a mesh is read several times, so \
         give a file on disk",
        path.display()
    )]
    NotAFile {
        /// The path.
        path: PathBuf,
    },
    /// An extension that names no supported format.
    #[error(
        "{} has extension {ext:?}: the mesh formats read are .stl (binary or ASCII), .obj and .ply",
        path.display()
    )]
    UnknownFormat {
        /// The file.
        path: PathBuf,
        /// Its extension.
        ext: String,
    },
    /// A binary STL whose length disagrees with its triangle count.
    #[error(
        "{} is a damaged binary STL: its header counts {count} triangles, which take {expected} \
         bytes, but the file has {actual} (truncated or with extra bytes)",
        path.display()
    )]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Triangles the header counts.
        count: u64,
        /// Bytes those need (84 + 50 per triangle).
        expected: u64,
        /// Bytes there are.
        actual: u64,
    },
    /// A vertex coordinate that is NaN or infinite.
    #[error("{}: triangle {index} has a vertex that is not a finite number ({vertex:?})", path.display())]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// The triangle, counting from 0 in file order.
        index: usize,
        /// The offending vertex.
        vertex: [f64; 3],
    },
    /// A face naming a vertex that is not there.
    #[error("{}: face {face} names vertex {vertex}, but there are only {count} vertices", path.display())]
    BadIndex {
        /// The file.
        path: PathBuf,
        /// The face, counting from 0.
        face: usize,
        /// The index it names.
        vertex: usize,
        /// Vertices in the file.
        count: usize,
    },
    /// Too few triangles to enclose anything.
    #[error("{} has {count} triangles; a closed surface needs at least 4", path.display())]
    TooFew {
        /// The file.
        path: PathBuf,
        /// Triangles found.
        count: usize,
    },
    /// The surface does not make a body the models can take.
    #[error("{}: {reason}", path.display())]
    Shape {
        /// The file.
        path: PathBuf,
        /// What is wrong and where.
        reason: String,
    },
    /// The fit asked for cannot be made.
    #[error("{0}")]
    Options(String),
}

/// A mesh file opened for reading its triangles, as many times as needed.
#[derive(Debug)]
pub struct MeshSource {
    path: PathBuf,
    format: MeshFormat,
    triangles: usize,
    /// OBJ and PLY, as loaded; empty for STL (streamed on each pass).
    held: Vec<[DVec3; 3]>,
    /// An ASCII STL (decided once, by [`MeshSource::check_stl`]).
    ascii: bool,
    /// A PLY file: its vertices held, its faces streamed.
    ply: Option<PlyStream>,
}

/// Most triangles accepted (a binary STL of this many is 5 GB).
pub const MAX_TRIANGLES: u64 = 100_000_000;

impl MeshSource {
    /// Opens `path`, finds its format from the extension (.stl, .obj, .ply, any case), and
    /// checks what can be checked before the first pass: a regular file, a binary STL's
    /// length, the OBJ or PLY loaded whole with its indices in range.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::mesh_read::{MeshError, MeshSource};
    /// // A device is refused before anything is read.
    /// let e = MeshSource::open(std::path::Path::new("/dev/zero")).unwrap_err();
    /// assert!(matches!(e, MeshError::NotAFile { .. }), "{e}");
    /// ```
    pub fn open(path: &Path) -> Result<Self, MeshError> {
        let read_error = |reason: String| MeshError::Read {
            path: path.to_path_buf(),
            reason,
        };
        let meta = std::fs::metadata(path).map_err(|e| read_error(e.to_string()))?;
        if !meta.is_file() {
            return Err(MeshError::NotAFile {
                path: path.to_path_buf(),
            });
        }
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            .unwrap_or_default();
        let format = match ext.as_str() {
            "stl" => MeshFormat::Stl,
            "obj" => MeshFormat::Obj,
            "ply" => MeshFormat::Ply,
            _ => {
                return Err(MeshError::UnknownFormat {
                    path: path.to_path_buf(),
                    ext,
                });
            }
        };
        let mut source = MeshSource {
            path: path.to_path_buf(),
            format,
            triangles: 0,
            held: Vec::new(),
            ascii: false,
            ply: None,
        };
        match format {
            MeshFormat::Stl => source.triangles = source.check_stl(meta.len())?,
            MeshFormat::Obj => {
                source.held = source.load_obj()?;
                source.triangles = source.held.len();
            }
            MeshFormat::Ply => {
                let stream = PlyStream::open(path).map_err(|e| source.ply_error(e))?;
                source.triangles = stream.triangles;
                source.ply = Some(stream);
            }
            // Not from a file: only [`MeshSource::made`] builds one.
            MeshFormat::Made => {}
        }
        if source.triangles < 4 {
            return Err(MeshError::TooFew {
                path: path.to_path_buf(),
                count: source.triangles,
            });
        }
        Ok(source)
    }

    /// A surface rollphase made, held in memory (`label` names it in reports and errors).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::mesh_read::{MeshFormat, MeshSource};
    /// use rollphase_core::glam::DVec3;
    /// let [o, x, y, z] = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
    /// let tet = MeshSource::made("a tetrahedron", vec![[o, y, x], [o, x, z], [o, z, y], [x, y, z]])?;
    /// assert_eq!((tet.format(), tet.triangles()), (MeshFormat::Made, 4));
    /// # Ok::<(), rollphase_core::geometry::mesh_read::MeshError>(())
    /// ```
    pub fn made(label: &str, triangles: Vec<[DVec3; 3]>) -> Result<Self, MeshError> {
        if triangles.len() < 4 {
            return Err(MeshError::TooFew {
                path: PathBuf::from(label),
                count: triangles.len(),
            });
        }
        Ok(MeshSource {
            path: PathBuf::from(label),
            format: MeshFormat::Made,
            triangles: triangles.len(),
            held: triangles,
            ascii: false,
            ply: None,
        })
    }

    /// The file.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::geometry::mesh_read::MeshSource;
    /// # let dir = std::env::temp_dir().join(format!("rp-doc-path-{}", std::process::id()));
    /// # std::fs::create_dir_all(&dir)?;
    /// # let path = dir.join("tet.obj");
    /// # std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")?;
    /// let mesh = MeshSource::open(&path)?;
    /// assert_eq!(mesh.path(), path.as_path());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The format read.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::geometry::mesh_read::{MeshFormat, MeshSource};
    /// # let dir = std::env::temp_dir().join(format!("rp-doc-format-{}", std::process::id()));
    /// # std::fs::create_dir_all(&dir)?;
    /// # let path = dir.join("tet.obj");
    /// # std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")?;
    /// assert_eq!(MeshSource::open(&path)?.format(), MeshFormat::Obj);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn format(&self) -> MeshFormat {
        self.format
    }

    /// Triangles in the file (polygons of an OBJ or PLY count as the triangles they are cut
    /// into).
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::geometry::mesh_read::MeshSource;
    /// # let dir = std::env::temp_dir().join(format!("rp-doc-count-{}", std::process::id()));
    /// # std::fs::create_dir_all(&dir)?;
    /// # let path = dir.join("tet.obj");
    /// # std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")?;
    /// assert_eq!(MeshSource::open(&path)?.triangles(), 4);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn triangles(&self) -> usize {
        self.triangles
    }

    /// Calls `f(index, [a, b, c])` for every triangle in file order, vertices in the file's
    /// winding; stops at the first error (a parse error, a non-finite vertex) or the first
    /// error `f` returns.
    ///
    /// # Example
    /// ```
    /// # use rollphase_core::geometry::mesh_read::MeshSource;
    /// # let dir = std::env::temp_dir().join(format!("rp-doc-each-{}", std::process::id()));
    /// # std::fs::create_dir_all(&dir)?;
    /// # let path = dir.join("tet.obj");
    /// # std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")?;
    /// let mut volume = 0.0;
    /// MeshSource::open(&path)?.for_each(|_, [a, b, c]| {
    ///     volume += a.dot(b.cross(c)) / 6.0;
    ///     Ok(())
    /// })?;
    /// assert!((volume - 1.0 / 6.0).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_each(
        &self,
        mut f: impl FnMut(usize, [DVec3; 3]) -> Result<(), MeshError>,
    ) -> Result<(), MeshError> {
        let mut visit = |index: usize, t: [DVec3; 3]| {
            if let Some(v) = t.iter().find(|v| !v.is_finite()) {
                return Err(MeshError::NonFinite {
                    path: self.path.clone(),
                    index,
                    vertex: v.to_array(),
                });
            }
            f(index, t)
        };
        if let Some(stream) = &self.ply {
            let mut failed = None;
            let streamed = stream.each(&self.path, |i, t| {
                visit(i, t).map_err(|e| {
                    failed = Some(e);
                    PlyError::Format(String::new())
                })
            });
            if let Some(e) = failed {
                return Err(e);
            }
            return streamed.map_err(|e| self.ply_error(e));
        }
        if self.format != MeshFormat::Stl {
            for (i, t) in self.held.iter().enumerate() {
                visit(i, *t)?;
            }
            return Ok(());
        }
        let file = File::open(&self.path).map_err(|e| self.read_error(e.to_string()))?;
        let mut reader = BufReader::with_capacity(1 << 20, file);
        if self.ascii {
            return self.each_ascii(reader, &mut visit);
        }
        let mut record = [0u8; 84];
        reader
            .read_exact(&mut record)
            .map_err(|e| self.read_error(format!("the 84-byte header: {e}")))?;
        let mut record = [0u8; 50];
        let float = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64;
        for i in 0..self.triangles {
            reader
                .read_exact(&mut record)
                .map_err(|e| self.read_error(format!("triangle {i}: {e}")))?;
            // The normal (bytes 0–12) is not read: the winding gives the outside, and exporters
            // write zeros or NaN there.
            let corner = |k: usize| {
                let b = &record[12 + 12 * k..24 + 12 * k];
                DVec3::new(float(&b[0..4]), float(&b[4..8]), float(&b[8..12]))
            };
            visit(i, [corner(0), corner(1), corner(2)])?;
        }
        Ok(())
    }

    /// An ASCII STL's triangles: the file as a stream of words (any case, any line ends), every
    /// solid in it; `facet normal` and its three values skipped unread.
    fn each_ascii(
        &self,
        reader: impl BufRead,
        visit: &mut impl FnMut(usize, [DVec3; 3]) -> Result<(), MeshError>,
    ) -> Result<(), MeshError> {
        let mut corners: Vec<DVec3> = Vec::with_capacity(3);
        let mut index = 0usize;
        let mut solids = 0usize;
        for (number, line) in reader.split(b'\n').enumerate() {
            let line = line.map_err(|e| self.read_error(e.to_string()))?;
            let line = String::from_utf8_lossy(&line);
            let at = |what: String| self.read_error(format!("line {}: {what}", number + 1));
            let mut words = line.split_whitespace();
            while let Some(word) = words.next() {
                match word.to_ascii_lowercase().as_str() {
                    // The rest of the line is the solid's name.
                    "solid" => {
                        solids += 1;
                        break;
                    }
                    "endsolid" => break,
                    "facet" => {
                        corners.clear();
                        // "normal" and its three values, which may be anything (nan).
                        for _ in 0..4 {
                            words.next();
                        }
                    }
                    "outer" | "loop" | "endloop" => {}
                    "vertex" => {
                        let mut v = [0.0; 3];
                        for x in &mut v {
                            let text = words.next().unwrap_or("");
                            *x = text.parse().map_err(|_| {
                                at(format!("vertex coordinate {text:?} is not a number"))
                            })?;
                        }
                        corners.push(DVec3::from_array(v));
                    }
                    "endfacet" => {
                        let Ok(t) = <[DVec3; 3]>::try_from(corners.as_slice()) else {
                            return Err(at(format!(
                                "a facet with {} vertices (an STL facet is a triangle: 3)",
                                corners.len()
                            )));
                        };
                        visit(index, t)?;
                        index += 1;
                        corners.clear();
                    }
                    other if solids == 0 => {
                        return Err(at(format!(
                            "{other:?} before any `solid`: not an ASCII STL file"
                        )));
                    }
                    other => {
                        return Err(at(format!(
                            "unexpected word {other:?} (an ASCII STL holds solid, facet normal, \
                             outer loop, vertex, endloop, endfacet and endsolid)"
                        )));
                    }
                }
            }
        }
        Ok(())
    }

    fn read_error(&self, reason: String) -> MeshError {
        MeshError::Read {
            path: self.path.clone(),
            reason,
        }
    }

    /// A binary STL's 80-byte header as text (trailing spaces and NULs trimmed); `None` for
    /// other formats, ASCII STL, or a header that cannot be read.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::{Disk, mesh::disk_mesh, mesh_read::MeshSource};
    /// let path = std::env::temp_dir().join(format!("header-{}.stl", std::process::id()));
    /// let mut bytes = Vec::new();
    /// disk_mesh(&Disk::perfect(), 64, 2.0).write_stl(&mut bytes, 10.0, "rod")?;
    /// std::fs::write(&path, bytes)?;
    /// let source = MeshSource::open(&path).unwrap();
    /// assert_eq!(source.stl_header().as_deref(), Some("rollphase rod"));
    /// # std::fs::remove_file(&path)?;
    /// # Ok::<(), std::io::Error>(())
    /// ```
    pub fn stl_header(&self) -> Option<String> {
        if self.format != MeshFormat::Stl || self.ascii {
            return None;
        }
        let mut header = [0u8; 80];
        File::open(&self.path).ok()?.read_exact(&mut header).ok()?;
        Some(
            String::from_utf8_lossy(&header)
                .trim_end_matches([' ', '\0'])
                .to_string(),
        )
    }

    /// The triangle count of an STL: a binary one's from its header, checked against the file's
    /// length; an ASCII one's by a first pass. Binary when the length is exactly a binary STL's
    /// for its header's count (some binary headers start with "solid"); otherwise ASCII when
    /// its first word is `solid` in any case; otherwise a damaged binary STL, named as such.
    fn check_stl(&mut self, len: u64) -> Result<usize, MeshError> {
        let mut file = File::open(&self.path).map_err(|e| self.read_error(e.to_string()))?;
        let mut head = vec![0u8; 1024.min(len as usize)];
        file.read_exact(&mut head)
            .map_err(|e| self.read_error(e.to_string()))?;
        let first_word = head
            .split(|b| b.is_ascii_whitespace())
            .find(|w| !w.is_empty())
            .unwrap_or(&[]);
        // Text has no NUL or other control bytes; a binary STL's count and floats do.
        let text = head
            .iter()
            .all(|&b| b >= 0x20 || b == b'\n' || b == b'\r' || b == b'\t');
        let head = &head[..84.min(head.len())];
        self.ascii =
            !binary_length_matches(head, len) && first_word.eq_ignore_ascii_case(b"solid") && text;
        if !self.ascii {
            if len < 84 {
                return Err(self.read_error(format!(
                    "{len} bytes is shorter than a binary STL's 84-byte header, and the file is \
                     not ASCII STL (which starts with `solid`)"
                )));
            }
            let count = u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64;
            let expected = 84 + 50 * count;
            if expected != len {
                return Err(MeshError::Truncated {
                    path: self.path.clone(),
                    count,
                    expected,
                    actual: len,
                });
            }
            self.triangles = count as usize;
            return Ok(count as usize);
        }
        let mut count = 0usize;
        self.for_each(|_, _| {
            count += 1;
            if count as u64 > MAX_TRIANGLES {
                return Err(self.read_error(format!("more than {MAX_TRIANGLES} triangles")));
            }
            Ok(())
        })?;
        Ok(count)
    }

    fn load_obj(&self) -> Result<Vec<[DVec3; 3]>, MeshError> {
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: false,
            ..Default::default()
        };
        let file = File::open(&self.path).map_err(|e| self.read_error(e.to_string()))?;
        let mut reader = BufReader::new(file);
        // Materials are irrelevant to the shape: a missing .mtl must not stop the read.
        let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
            Ok((Vec::new(), Default::default()))
        })
        .map_err(|e| self.read_error(format!("not a readable OBJ file: {e}")))?;
        let mut out = Vec::new();
        let mut face = 0usize;
        for model in &models {
            let m = &model.mesh;
            let count = m.positions.len() / 3;
            for tri in m.indices.chunks_exact(3) {
                let mut t = [DVec3::ZERO; 3];
                for (k, &i) in tri.iter().enumerate() {
                    let i = i as usize;
                    if i >= count {
                        return Err(MeshError::BadIndex {
                            path: self.path.clone(),
                            face,
                            vertex: i,
                            count,
                        });
                    }
                    t[k] = DVec3::new(
                        m.positions[3 * i] as f64,
                        m.positions[3 * i + 1] as f64,
                        m.positions[3 * i + 2] as f64,
                    );
                }
                out.push(t);
                face += 1;
            }
        }
        Ok(out)
    }

    /// A PLY stream's error as a [`MeshError`] naming the file.
    fn ply_error(&self, e: PlyError) -> MeshError {
        match e {
            PlyError::Format(reason) => self.read_error(reason),
            PlyError::Index {
                face,
                vertex,
                count,
            } => MeshError::BadIndex {
                path: self.path.clone(),
                face,
                vertex,
                count,
            },
        }
    }
}

/// Whether a file of `len` bytes starting with `head` is exactly a binary STL's length (some
/// binary STLs start their header with "solid", as ASCII ones do).
fn binary_length_matches(head: &[u8], len: u64) -> bool {
    head.len() == 84
        && 84 + 50 * u32::from_le_bytes([head[80], head[81], head[82], head[83]]) as u64 == len
}
