//! PLY read as a stream: the header parsed here, the faces read from disk on every pass a block
//! of corners at a time and cut into triangles as a fan. A binary file's vertex records (one
//! size each) are read from disk as a block names them, sorted so each is read once in file
//! order, so memory stays flat (within 1.4× of a streamed binary STL at 5 M triangles) however
//! the faces jump across the vertices. An ASCII file's lines have no fixed length to seek by, so
//! its vertices' x, y, z are held (12 bytes a vertex where the coordinates fit an f32 exactly,
//! as scanners and exporters write them; 24 otherwise).
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

/// A PLY file opened for streaming: where its vertices are (held, or read from disk as the
/// faces name them), where its faces start, and how many triangles they make.
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

/// The vertices: read from disk in blocks where their records have one size (binary files whose
/// vertex has no list property, which is every scanner's and exporter's), held otherwise
/// (ASCII lines have no fixed length to seek by).
#[derive(Debug, Clone)]
enum Vertices {
    /// Held as compactly as their declared type allows without changing a bit.
    Single(Vec<[f32; 3]>),
    /// Held in full precision.
    Double(Vec<DVec3>),
    /// Binary records of one size, read where a block of faces needs them.
    OnDisk(VertexRecords),
}

/// Where binary vertex records of one size lie, and where x, y, z lie in each.
#[derive(Debug, Clone, Copy)]
struct VertexRecords {
    /// The first record's offset in the file.
    start: u64,
    /// Bytes a record.
    size: usize,
    /// Records.
    count: usize,
    /// x, y, z: each one's offset in the record and its type.
    xyz: [(usize, Scalar); 3],
}

/// Corners resolved together: a block's faces are gathered until they name this many corners,
/// their vertex records are read in file order, and its triangles are handed on. It bounds
/// what a pass holds (8 bytes of sort key and 24 of position a corner, 4 MB) whatever the
/// mesh's size. 5.2 M triangles then take 120 forward sweeps over the vertex records a pass:
/// through `shape --from-mesh` 28.5 MB and 12.5 s, where holding the vertices took 53.0 MB and
/// 15.7 s (and 2¹⁸ corners 34.7 MB, 11.3 s).
const CORNERS_PER_BLOCK: usize = 1 << 17;

impl Vertices {
    fn len(&self) -> usize {
        match self {
            Vertices::Single(v) => v.len(),
            Vertices::Double(v) => v.len(),
            Vertices::OnDisk(records) => records.count,
        }
    }

    fn push(&mut self, p: DVec3) {
        match self {
            // Exact: the declared types fit an f32.
            #[allow(clippy::cast_possible_truncation)]
            Vertices::Single(v) => v.push([p.x as f32, p.y as f32, p.z as f32]),
            Vertices::Double(v) => v.push(p),
            Vertices::OnDisk(_) => {}
        }
    }

    /// Fills `at` with the position of each of `corners` (vertex indices already checked),
    /// reading records from `file` in ascending order when they are on disk; `order` is
    /// scratch space kept between blocks.
    fn resolve(
        &self,
        corners: &[u32],
        at: &mut Vec<DVec3>,
        order: &mut Vec<u64>,
        file: &mut Option<BufReader<File>>,
        encoding: Encoding,
    ) -> Result<(), PlyError> {
        at.clear();
        match self {
            Vertices::Single(v) => at.extend(corners.iter().map(|&c| {
                let [x, y, z] = v[c as usize];
                DVec3::new(f64::from(x), f64::from(y), f64::from(z))
            })),
            Vertices::Double(v) => at.extend(corners.iter().map(|&c| v[c as usize])),
            Vertices::OnDisk(records) => {
                let reader = file
                    .as_mut()
                    .ok_or_else(|| format("the vertex records are not open"))?;
                at.resize(corners.len(), DVec3::ZERO);
                // Sorting (vertex, corner) keys turns the faces' jumps across the vertex block
                // into one forward sweep, each record read once however many corners share it.
                order.clear();
                order.extend(
                    corners
                        .iter()
                        .enumerate()
                        .map(|(k, &c)| (u64::from(c) << 32) | k as u64),
                );
                order.sort_unstable();
                let mut record = vec![0u8; records.size];
                let mut position = reader
                    .stream_position()
                    .map_err(|e| format(e.to_string()))?;
                let mut current = None;
                let mut value = DVec3::ZERO;
                for &key in order.iter() {
                    let vertex = key >> 32;
                    if current != Some(vertex) {
                        let wanted = records.start + vertex * records.size as u64;
                        #[allow(clippy::cast_possible_wrap)]
                        reader
                            .seek_relative(wanted as i64 - position as i64)
                            .map_err(|e| format(e.to_string()))?;
                        reader.read_exact(&mut record).map_err(|e| {
                            format(format!("vertex {vertex}: the file ends inside it ({e})"))
                        })?;
                        position = wanted + records.size as u64;
                        let [x, y, z] = records.xyz.map(|(offset, kind)| {
                            kind.decode(&record[offset..offset + kind.size()], encoding)
                        });
                        value = DVec3::new(x, y, z);
                        current = Some(vertex);
                    }
                    at[(key & 0xffff_ffff) as usize] = value;
                }
            }
        }
        Ok(())
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
    /// Opens `path`: reads the header, finds the vertex records (holding them unless they can
    /// be read from disk), and walks the faces once to count the triangles and check every
    /// index.
    pub(crate) fn open(path: &Path) -> Result<PlyStream, PlyError> {
        let file = File::open(path).map_err(|e| format(e.to_string()))?;
        let length = file.metadata().map_err(|e| format(e.to_string()))?.len();
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
        let vertex = &elements[vertex_at];
        let fixed_size = (encoding != Encoding::Ascii)
            .then(|| {
                vertex
                    .properties
                    .iter()
                    .try_fold(0usize, |size, p| match p {
                        Property::Scalar(_, k) => Some(size + k.size()),
                        Property::List(..) => None,
                    })
            })
            .flatten();
        let single = [x, y, z].iter().all(|&p| {
            matches!(
                vertex.properties[p],
                Property::Scalar(
                    _,
                    Scalar::F32 | Scalar::I8 | Scalar::U8 | Scalar::I16 | Scalar::U16
                )
            )
        });
        let mut vertices = if single {
            Vertices::Single(Vec::new())
        } else {
            Vertices::Double(Vec::new())
        };
        let mut records = Records::new(reader, encoding, header_len);
        let mut face_start = header_len;
        let mut values = Vec::new();
        for (k, element) in elements.iter().enumerate() {
            if k == face_at {
                face_start = records.position();
                if face_at < vertex_at {
                    // Faces before vertices: skip them now, read them by seeking later.
                    for i in 0..element.count {
                        records.record(element, &mut values, || format!("face {i}"))?;
                    }
                    continue;
                }
                break;
            }
            if k == vertex_at
                && let Some(size) = fixed_size
            {
                let start = records.position();
                let end = element
                    .count
                    .checked_mul(size as u64)
                    .and_then(|bytes| bytes.checked_add(start))
                    .filter(|&end| end <= length)
                    .ok_or_else(|| {
                        format(format!(
                            "the file ends inside its {} vertex records of {size} bytes",
                            element.count
                        ))
                    })?;
                let offset = |p: usize| {
                    let at = vertex.properties[..p].iter().map(|q| match q {
                        Property::Scalar(_, k) => k.size(),
                        Property::List(..) => 0,
                    });
                    let Property::Scalar(_, kind) = vertex.properties[p] else {
                        unreachable!("x, y and z are scalar properties")
                    };
                    (at.sum(), kind)
                };
                vertices = Vertices::OnDisk(VertexRecords {
                    start,
                    size,
                    count: element.count as usize,
                    xyz: [offset(x), offset(y), offset(z)],
                });
                records.skip_to(end)?;
                continue;
            }
            for i in 0..element.count {
                records.record(element, &mut values, || format!("{} {i}", element.name))?;
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

    /// Calls `f(index, triangle)` for each triangle, in file order, reading the faces (and the
    /// vertex records, when they are not held) from disk a block of corners at a time.
    pub(crate) fn each(
        &self,
        path: &Path,
        mut f: impl FnMut(usize, [DVec3; 3]) -> Result<(), PlyError>,
    ) -> Result<(), PlyError> {
        let open = |at: u64| -> Result<BufReader<File>, PlyError> {
            let mut file = File::open(path).map_err(|e| format(e.to_string()))?;
            file.seek(SeekFrom::Start(at))
                .map_err(|e| format(e.to_string()))?;
            Ok(BufReader::with_capacity(1 << 20, file))
        };
        let mut records = Records::new(open(self.face_start)?, self.encoding, self.face_start);
        let mut vertex_file = match self.vertices {
            Vertices::OnDisk(v) => Some(open(v.start)?),
            _ => None,
        };
        let n = self.vertices.len();
        let mut values = Vec::new();
        let mut corners: Vec<u32> = Vec::new();
        let mut sides: Vec<u32> = Vec::new();
        let mut at = Vec::new();
        let mut order = Vec::new();
        let mut index = 0usize;
        let faces = self.face.count as usize;
        let mut face = 0;
        while face < faces {
            corners.clear();
            sides.clear();
            while face < faces && corners.len() < CORNERS_PER_BLOCK {
                records.record(&self.face, &mut values, || format!("face {face}"))?;
                let list = &values[self.list];
                for &c in list {
                    if !(c >= 0.0 && c.fract() == 0.0 && (c as usize) < n) {
                        return Err(PlyError::Index {
                            face,
                            vertex: if c >= 0.0 { c as usize } else { 0 },
                            count: n,
                        });
                    }
                    // n ≤ MAX_COUNT < 2³²: the index fits.
                    #[allow(clippy::cast_possible_truncation)]
                    corners.push(c as u32);
                }
                // A list holds at most 10⁶ items (checked as it is read).
                #[allow(clippy::cast_possible_truncation)]
                sides.push(list.len() as u32);
                face += 1;
            }
            self.vertices.resolve(
                &corners,
                &mut at,
                &mut order,
                &mut vertex_file,
                self.encoding,
            )?;
            let mut first = 0;
            for &k in &sides {
                let k = k as usize;
                for j in 1..k.saturating_sub(1) {
                    f(index, [at[first], at[first + j], at[first + j + 1]])?;
                    index += 1;
                }
                first += k;
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

impl Records<BufReader<File>> {
    /// Moves on to byte `end` (at or after the next record) without reading what lies between.
    fn skip_to(&mut self, end: u64) -> Result<(), PlyError> {
        let ahead = end
            .checked_sub(self.position)
            .and_then(|d| i64::try_from(d).ok())
            .ok_or_else(|| format("a PLY element lies before the one already read"))?;
        self.reader
            .seek_relative(ahead)
            .map_err(|e| format(e.to_string()))?;
        self.position = end;
        Ok(())
    }
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
        what: impl Fn() -> String,
    ) -> Result<(), PlyError> {
        values.resize(element.properties.len(), Vec::new());
        for v in values.iter_mut() {
            v.clear();
        }
        let cut = |e: std::io::Error| format(format!("{}: the file ends inside it ({e})", what()));
        if self.encoding == Encoding::Ascii {
            self.line.clear();
            let read = self.reader.read_line(&mut self.line).map_err(cut)?;
            if read == 0 {
                return Err(format(format!("{}: the file ends before it", what())));
            }
            self.position += read as u64;
            let mut words = self.line.split_whitespace();
            let number = |words: &mut std::str::SplitWhitespace| -> Result<f64, PlyError> {
                let w = words
                    .next()
                    .ok_or_else(|| format(format!("{}: the line has too few values", what())))?;
                w.parse()
                    .map_err(|_| format(format!("{}: {w:?} is not a number", what())))
            };
            for (p, v) in element.properties.iter().zip(values.iter_mut()) {
                match p {
                    Property::Scalar(..) => v.push(number(&mut words)?),
                    Property::List(..) => {
                        let n = number(&mut words)?;
                        if !(0.0..=1e6).contains(&n) {
                            return Err(format(format!("{}: a list of {n} items", what())));
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
                        return Err(format(format!("{}: a list of {n} items", what())));
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
