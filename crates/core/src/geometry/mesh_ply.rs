//! PLY read as a stream: the header parsed here, the vertices' x, y, z held (12 bytes a vertex
//! where the file's coordinates fit an f32 exactly, as scanners and exporters write them; 24
//! otherwise), the faces read from disk on every pass and cut into triangles as a fan.
//!
//! Written here rather than through `ply-rs-bw` because that crate builds every element as a
//! map of named properties: a 97 MB binary PLY of 5.1 M triangles took 3.5 GB and 19 s, 37
//! times its size, where the same mesh as a binary STL, streamed, takes a few tens of MB. The
//! format is small: a text header of `element NAME COUNT` lines each followed by its
//! `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME` lines, then the elements'
//! records in order, as ASCII lines or packed little- or big-endian binary. Every element is
//! read (or skipped) by its declared properties, so comments, extra properties (normals,
//! colours, texture coordinates) and extra elements (edges, materials) anywhere are passed over.

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use glam::DVec3;

/// How the records are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// A scalar type of the PLY header.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// The value of `b` (exactly [`Self::size`] bytes).
    fn decode(self, b: &[u8], encoding: Encoding) -> f64 {
        macro_rules! num {
            ($t:ty) => {{
                let a = b.try_into().unwrap_or_default();
                (if encoding == Encoding::Big {
                    <$t>::from_be_bytes(a)
                } else {
                    <$t>::from_le_bytes(a)
                }) as f64
            }};
        }
        match self {
            Scalar::I8 => num!(i8),
            Scalar::U8 => num!(u8),
            Scalar::I16 => num!(i16),
            Scalar::U16 => num!(u16),
            Scalar::I32 => num!(i32),
            Scalar::U32 => num!(u32),
            Scalar::F32 => num!(f32),
            Scalar::F64 => num!(f64),
        }
    }
}

/// One property of an element.
#[derive(Debug, Clone, PartialEq)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

/// One element of the header.
#[derive(Debug, Clone, PartialEq)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
}

/// A PLY file opened for streaming: its vertices held, where its faces start, and how many
/// triangles they make.
#[derive(Debug, Clone)]
pub(crate) struct PlyStream {
    encoding: Encoding,
    vertices: Vertices,
    face: Element,
    /// Which of the face's properties is the vertex index list.
    list: usize,
    /// Where the face records start (bytes from the file's start).
    face_start: u64,
    /// Triangles the faces make (a polygon of k corners makes k − 2).
    pub(crate) triangles: usize,
}

/// The vertices held, as compactly as their declared type allows without changing a bit.
#[derive(Debug, Clone)]
enum Vertices {
    Single(Vec<[f32; 3]>),
    Double(Vec<DVec3>),
}

impl Vertices {
    fn len(&self) -> usize {
        match self {
            Vertices::Single(v) => v.len(),
            Vertices::Double(v) => v.len(),
        }
    }

    fn get(&self, i: usize) -> DVec3 {
        match self {
            Vertices::Single(v) => {
                let [x, y, z] = v[i];
                DVec3::new(f64::from(x), f64::from(y), f64::from(z))
            }
            Vertices::Double(v) => v[i],
        }
    }

    fn push(&mut self, p: DVec3) {
        match self {
            // Exact: the declared types fit an f32.
            #[allow(clippy::cast_possible_truncation)]
            Vertices::Single(v) => v.push([p.x as f32, p.y as f32, p.z as f32]),
            Vertices::Double(v) => v.push(p),
        }
    }
}

/// Most records of one element accepted (a sanity bound on the header's counts).
const MAX_COUNT: u64 = 1_000_000_000;
/// The longest header line read.
const MAX_HEADER_LINE: usize = 4096;

/// What can go wrong, as one sentence for [`super::mesh_read::MeshError::Read`] (or, for a face
/// index out of range, its face, index and the vertex count).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PlyError {
    /// Anything else.
    Format(String),
    /// Face `face` names vertex `vertex` of `count`.
    Index {
        /// The face.
        face: usize,
        /// The index it names.
        vertex: usize,
        /// Vertices in the file.
        count: usize,
    },
}

fn format(s: impl Into<String>) -> PlyError {
    PlyError::Format(s.into())
}

impl PlyStream {
    /// Opens `path`: reads the header, holds the vertices, and walks the faces once to count
    /// the triangles and check every index.
    pub(crate) fn open(path: &Path) -> Result<PlyStream, PlyError> {
        let file = File::open(path).map_err(|e| format(e.to_string()))?;
        let mut reader = BufReader::with_capacity(1 << 20, file);
        let (encoding, elements, header_len) = header(&mut reader)?;
        let vertex_at = elements.iter().position(|e| e.name == "vertex");
        let face_at = elements.iter().position(|e| e.name == "face");
        let (Some(vertex_at), Some(face_at)) = (vertex_at, face_at) else {
            return Err(format(
                "a PLY mesh needs a `vertex` element with x, y, z and a `face` element with \
                 vertex_indices; the header has no `vertex` or no `face` element",
            ));
        };
        let coordinate = |name: &str| {
            elements[vertex_at]
                .properties
                .iter()
                .position(|p| matches!(p, Property::Scalar(n, _) if n == name))
        };
        let (Some(x), Some(y), Some(z)) = (coordinate("x"), coordinate("y"), coordinate("z"))
        else {
            return Err(format(
                "a PLY mesh needs a `vertex` element with x, y, z (scalar properties); they are \
                 missing",
            ));
        };
        let list = elements[face_at]
            .properties
            .iter()
            .position(|p| {
                matches!(p, Property::List(n, _, _) if n == "vertex_indices" || n == "vertex_index")
            })
            .ok_or_else(|| {
                format("a PLY `face` element needs a list property vertex_indices (or vertex_index)")
            })?;
        let single = [x, y, z].iter().all(|&p| {
            matches!(
                elements[vertex_at].properties[p],
                Property::Scalar(
                    _,
                    Scalar::F32 | Scalar::I8 | Scalar::U8 | Scalar::I16 | Scalar::U16
                )
            )
        });
        let mut records = Records::new(reader, encoding, header_len);
        let mut vertices = if single {
            Vertices::Single(Vec::new())
        } else {
            Vertices::Double(Vec::new())
        };
        let mut face_start = header_len;
        let mut values = Vec::new();
        for (k, element) in elements.iter().enumerate() {
            if k == face_at {
                face_start = records.position();
                if face_at < vertex_at {
                    // Faces before vertices: skip them now, read them by seeking later.
                    for i in 0..element.count {
                        records.record(element, &mut values, &format!("face {i}"))?;
                    }
                    continue;
                }
                break;
            }
            for i in 0..element.count {
                records.record(element, &mut values, &format!("{} {i}", element.name))?;
                if k == vertex_at {
                    vertices.push(DVec3::new(values[x][0], values[y][0], values[z][0]));
                }
            }
        }
        let mut stream = PlyStream {
            encoding,
            vertices,
            face: elements[face_at].clone(),
            list,
            face_start,
            triangles: 0,
        };
        let mut triangles = 0usize;
        stream.each(path, |_, _| {
            triangles += 1;
            Ok(())
        })?;
        stream.triangles = triangles;
        Ok(stream)
    }

    /// Calls `f(index, triangle)` for each triangle, in file order, reading the faces from disk.
    pub(crate) fn each(
        &self,
        path: &Path,
        mut f: impl FnMut(usize, [DVec3; 3]) -> Result<(), PlyError>,
    ) -> Result<(), PlyError> {
        let mut file = File::open(path).map_err(|e| format(e.to_string()))?;
        file.seek(SeekFrom::Start(self.face_start))
            .map_err(|e| format(e.to_string()))?;
        let reader = BufReader::with_capacity(1 << 20, file);
        let mut records = Records::new(reader, self.encoding, self.face_start);
        let mut values = Vec::new();
        let mut index = 0usize;
        let n = self.vertices.len();
        for face in 0..self.face.count as usize {
            records.record(&self.face, &mut values, &format!("face {face}"))?;
            let corners = &values[self.list];
            let mut at = Vec::with_capacity(corners.len());
            for &c in corners {
                if !(c >= 0.0 && c.fract() == 0.0 && (c as usize) < n) {
                    return Err(PlyError::Index {
                        face,
                        vertex: if c >= 0.0 { c as usize } else { 0 },
                        count: n,
                    });
                }
                at.push(self.vertices.get(c as usize));
            }
            for k in 1..at.len().saturating_sub(1) {
                f(index, [at[0], at[k], at[k + 1]])?;
                index += 1;
            }
        }
        Ok(())
    }
}

/// Reads the header: the encoding, the elements, and the header's length in bytes.
fn header(reader: &mut impl BufRead) -> Result<(Encoding, Vec<Element>, u64), PlyError> {
    let mut length = 0u64;
    let mut line = Vec::new();
    let mut next_line = |reader: &mut dyn BufRead| -> Result<Option<String>, PlyError> {
        line.clear();
        let read = reader
            .take(MAX_HEADER_LINE as u64 + 1)
            .read_until(b'\n', &mut line)
            .map_err(|e| format(e.to_string()))?;
        if read == 0 {
            return Ok(None);
        }
        if read > MAX_HEADER_LINE {
            return Err(format(
                "a PLY header line longer than 4096 bytes: not a PLY header",
            ));
        }
        length += read as u64;
        Ok(Some(String::from_utf8_lossy(&line).trim().to_string()))
    };
    if next_line(reader)?.as_deref() != Some("ply") {
        return Err(format(
            "not a PLY file: it does not start with the line `ply`",
        ));
    }
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some(text) = next_line(reader)? else {
            return Err(format("the PLY header has no `end_header` line"));
        };
        let words: Vec<&str> = text.split_whitespace().collect();
        match words.as_slice() {
            ["end_header"] => break,
            [] | ["comment", ..] | ["obj_info", ..] => {}
            ["format", kind, _version] => {
                encoding = Some(match *kind {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    other => return Err(format(format!("PLY format {other:?} is not known"))),
                });
            }
            ["element", name, count] => {
                let count: u64 =
                    count
                        .parse()
                        .ok()
                        .filter(|&c| c <= MAX_COUNT)
                        .ok_or_else(|| {
                            format(format!("element {name}: count {count:?} is not allowed"))
                        })?;
                elements.push(Element {
                    name: (*name).to_string(),
                    count,
                    properties: Vec::new(),
                });
            }
            ["property", "list", count, item, name] => {
                let (Some(c), Some(i)) = (Scalar::parse(count), Scalar::parse(item)) else {
                    return Err(format(format!(
                        "property list {count} {item}: unknown type"
                    )));
                };
                let element = elements
                    .last_mut()
                    .ok_or_else(|| format("a PLY property before any element"))?;
                element
                    .properties
                    .push(Property::List((*name).to_string(), c, i));
            }
            ["property", kind, name] => {
                let k = Scalar::parse(kind)
                    .ok_or_else(|| format(format!("property {name}: unknown type {kind:?}")))?;
                let element = elements
                    .last_mut()
                    .ok_or_else(|| format("a PLY property before any element"))?;
                element
                    .properties
                    .push(Property::Scalar((*name).to_string(), k));
            }
            _ => {
                return Err(format(format!(
                    "PLY header line {text:?} is not understood"
                )));
            }
        }
    }
    let encoding = encoding.ok_or_else(|| format("the PLY header has no `format` line"))?;
    Ok((encoding, elements, length))
}

/// Records read one by one, each property's values into a reused buffer.
struct Records<R> {
    reader: R,
    encoding: Encoding,
    position: u64,
    line: String,
}

impl<R: BufRead> Records<R> {
    fn new(reader: R, encoding: Encoding, position: u64) -> Self {
        Records {
            reader,
            encoding,
            position,
            line: String::new(),
        }
    }

    /// Bytes from the file's start to the next record.
    fn position(&self) -> u64 {
        self.position
    }

    /// Reads one record of `element`: `values[p]` gets property p's values (one for a scalar).
    fn record(
        &mut self,
        element: &Element,
        values: &mut Vec<Vec<f64>>,
        what: &str,
    ) -> Result<(), PlyError> {
        values.resize(element.properties.len(), Vec::new());
        for v in values.iter_mut() {
            v.clear();
        }
        let cut = |e: std::io::Error| format(format!("{what}: the file ends inside it ({e})"));
        if self.encoding == Encoding::Ascii {
            self.line.clear();
            let read = self.reader.read_line(&mut self.line).map_err(cut)?;
            if read == 0 {
                return Err(format(format!("{what}: the file ends before it")));
            }
            self.position += read as u64;
            let mut words = self.line.split_whitespace();
            let number = |words: &mut std::str::SplitWhitespace| -> Result<f64, PlyError> {
                let w = words
                    .next()
                    .ok_or_else(|| format(format!("{what}: the line has too few values")))?;
                w.parse()
                    .map_err(|_| format(format!("{what}: {w:?} is not a number")))
            };
            for (p, v) in element.properties.iter().zip(values.iter_mut()) {
                match p {
                    Property::Scalar(..) => v.push(number(&mut words)?),
                    Property::List(..) => {
                        let n = number(&mut words)?;
                        if !(0.0..=1e6).contains(&n) {
                            return Err(format(format!("{what}: a list of {n} items")));
                        }
                        for _ in 0..n as usize {
                            v.push(number(&mut words)?);
                        }
                    }
                }
            }
            return Ok(());
        }
        let mut buf = [0u8; 8];
        let encoding = self.encoding;
        let mut read =
            |kind: Scalar, reader: &mut R, position: &mut u64| -> Result<f64, PlyError> {
                let b = &mut buf[..kind.size()];
                reader.read_exact(b).map_err(cut)?;
                *position += b.len() as u64;
                Ok(kind.decode(b, encoding))
            };
        for (p, v) in element.properties.iter().zip(values.iter_mut()) {
            match *p {
                Property::Scalar(_, k) => v.push(read(k, &mut self.reader, &mut self.position)?),
                Property::List(_, c, i) => {
                    let n = read(c, &mut self.reader, &mut self.position)?;
                    if !(0.0..=1e6).contains(&n) {
                        return Err(format(format!("{what}: a list of {n} items")));
                    }
                    for _ in 0..n as usize {
                        v.push(read(i, &mut self.reader, &mut self.position)?);
                    }
                }
            }
        }
        Ok(())
    }
}
