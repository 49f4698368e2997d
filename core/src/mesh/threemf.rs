//! 3MF (3D Manufacturing Format, core specification 1.3): the format
//! current slicers prefer, with an explicit unit, object names and several
//! objects on one build plate.
//!
//! **Writing.** One package (a zip: `[Content_Types].xml`, `_rels/.rels`,
//! `3D/3dmodel.model`) whose model says `unit="millimeter"` and carries
//! the scale in the vertices (PrusaSlicer and Bambu Studio apply the unit
//! to vertices but not to build-item translations, so no transforms are
//! written). Each connected piece of the printable mesh is one `object`
//! with one build `item` (an object without an item is dropped by
//! readers), named after the document objects whose triangles it holds
//! (`Body + Spout`). Coordinates are the float32 millimetre values the STL
//! writer writes, printed in their shortest exact form, so the file holds
//! exactly the model the print path validated (precision F32 in mm).
//!
//! Why our own writer rather than the `threemf` crate: the model part is a
//! few lines of XML, and writing it here controls what the print path
//! relies on (the float32 values, one item per object, names escaped);
//! `threemf` 0.8 writes f64 text and would add a second zip version to the
//! build. Zipping uses the `zip` crate (already in the build for USD).
//!
//! **Reading** (for `info`, outside data): the model part named by the
//! package relationships (or `3D/3dmodel.model`), parsed with `quick-xml`;
//! the model's unit (micron, millimeter, centimeter, inch, foot, meter),
//! mesh objects, component objects and build items with their transforms
//! are honoured; the build's items are flattened into one mesh in metres,
//! each item's triangles tagged with its index. Sizes are checked before
//! anything is reserved and references are resolved with a depth limit,
//! so a hostile file is refused, never a panic or a runaway allocation.
#![deny(clippy::indexing_slicing)]

use std::collections::BTreeMap;
use std::io::{Cursor, Read, Write};

use super::{MeshIoError, PartNames, TriMesh};

/// The 3MF core namespace.
const CORE_NS: &str = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02";
/// Where our writer puts the model.
const MODEL_PATH: &str = "3D/3dmodel.model";
/// Millimetres per metre.
const MM: f64 = 1000.0;

const CONTENT_TYPES: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>
"#;

const RELS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>
"#;

/// Writes `mesh` (metres) as a 3MF package in millimetres, one object and
/// build item per connected piece, named from `names` by the pieces'
/// triangle sources.
pub fn write_3mf(mesh: &TriMesh, names: &PartNames, w: &mut impl Write) -> std::io::Result<()> {
    let model = model_xml(mesh, names);
    let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
    // The same bytes on every OS (issue 32): the zip crate's default
    // "made by" system is the build's own (Unix here, DOS on Windows).
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .last_modified_time(zip::DateTime::default())
        .system(zip::System::Unix);
    let io = |e: zip::result::ZipError| std::io::Error::other(e.to_string());
    for (name, text) in [
        ("[Content_Types].xml", CONTENT_TYPES),
        ("_rels/.rels", RELS),
        (MODEL_PATH, model.as_str()),
    ] {
        zip.start_file(name, options).map_err(io)?;
        zip.write_all(text.as_bytes())?;
    }
    let bytes = zip.finish().map_err(io)?.into_inner();
    w.write_all(&bytes)
}

/// The connected pieces of `mesh` (triangles sharing a vertex), each as
/// its triangles' indices, in order of their first triangle.
fn pieces(mesh: &TriMesh) -> Vec<Vec<usize>> {
    let n = mesh.positions.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while let Some(&p) = parent.get(i) {
            if p == i {
                break;
            }
            let gp = parent.get(p).copied().unwrap_or(p);
            if let Some(slot) = parent.get_mut(i) {
                *slot = gp;
            }
            i = p;
        }
        i
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i as usize);
        for (x, y) in [(a, b), (a, c)] {
            let (rx, ry) = (find(&mut parent, x), find(&mut parent, y));
            if rx != ry {
                if let Some(slot) = parent.get_mut(rx.max(ry)) {
                    *slot = rx.min(ry);
                }
            }
        }
    }
    let mut by_root: BTreeMap<usize, usize> = BTreeMap::new();
    let mut out: Vec<Vec<usize>> = Vec::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let root = find(&mut parent, tri[0] as usize);
        let k = *by_root.entry(root).or_insert_with(|| {
            out.push(Vec::new());
            out.len() - 1
        });
        if let Some(piece) = out.get_mut(k) {
            piece.push(t);
        }
    }
    out
}

/// The name of a piece: the names of its triangles' objects, in id order.
fn piece_name(mesh: &TriMesh, piece: &[usize], names: &PartNames) -> String {
    let mut ids: Vec<u32> = piece
        .iter()
        .filter_map(|&t| mesh.tri_source.get(t).copied())
        .collect();
    ids.sort_unstable();
    ids.dedup();
    if ids.is_empty() {
        return "Shapewright model".into();
    }
    ids.iter()
        .map(|id| names.get(id).cloned().unwrap_or(format!("object {id}")))
        .collect::<Vec<_>>()
        .join(" + ")
}

/// `text` escaped for an XML attribute value.
fn escape(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => s.push_str("&amp;"),
            '<' => s.push_str("&lt;"),
            '>' => s.push_str("&gt;"),
            '"' => s.push_str("&quot;"),
            '\'' => s.push_str("&apos;"),
            // Control characters other than tab/newline are not XML.
            c if (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => s.push(' '),
            c => s.push(c),
        }
    }
    s
}

fn model_xml(mesh: &TriMesh, names: &PartNames) -> String {
    use std::fmt::Write as _;
    let mut s = String::with_capacity(mesh.vertex_count() * 48 + mesh.triangle_count() * 40);
    s.push_str(r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = write!(
        s,
        "\n<model unit=\"millimeter\" xml:lang=\"en-US\" xmlns=\"{CORE_NS}\">\n \
         <metadata name=\"Application\">Shapewright</metadata>\n <resources>\n"
    );
    let pieces = pieces(mesh);
    for (k, piece) in pieces.iter().enumerate() {
        let name = escape(&piece_name(mesh, piece, names));
        let _ = write!(
            s,
            "  <object id=\"{}\" type=\"model\" name=\"{name}\">\n   <mesh>\n    <vertices>\n",
            k + 1
        );
        let mut local: BTreeMap<u32, u32> = BTreeMap::new();
        let mut order: Vec<u32> = Vec::new();
        for &t in piece {
            for v in mesh.triangles.get(t).copied().unwrap_or_default() {
                local.entry(v).or_insert_with(|| {
                    order.push(v);
                    (order.len() - 1) as u32
                });
            }
        }
        for v in &order {
            let p = mesh.positions.get(*v as usize).copied().unwrap_or_default();
            let [x, y, z] = p.map(|c| (c * MM) as f32);
            let _ = writeln!(s, "     <vertex x=\"{x}\" y=\"{y}\" z=\"{z}\"/>");
        }
        s.push_str("    </vertices>\n    <triangles>\n");
        for &t in piece {
            let [a, b, c] = mesh
                .triangles
                .get(t)
                .copied()
                .unwrap_or_default()
                .map(|v| local.get(&v).copied().unwrap_or(0));
            let _ = writeln!(s, "     <triangle v1=\"{a}\" v2=\"{b}\" v3=\"{c}\"/>");
        }
        s.push_str("    </triangles>\n   </mesh>\n  </object>\n");
    }
    s.push_str(" </resources>\n <build>\n");
    for k in 0..pieces.len() {
        let _ = writeln!(s, "  <item objectid=\"{}\"/>", k + 1);
    }
    s.push_str(" </build>\n</model>\n");
    s
}

/// Largest model part read (uncompressed bytes): 1 GiB.
const MAX_MODEL_BYTES: u64 = 1 << 30;
/// Deepest component nesting followed.
const MAX_DEPTH: usize = 16;
/// Most triangles a flattened build may have (components can repeat an
/// object; this bounds the output, not the file).
const MAX_TRIANGLES: usize = 100_000_000;

fn bad(message: impl Into<String>) -> MeshIoError {
    MeshIoError::BadData {
        offset: 0,
        message: message.into(),
    }
}

/// A 3MF object: a mesh, or components (object id and transform).
enum Object {
    Mesh(TriMesh),
    Components(Vec<(u32, Affine)>),
}

/// A 3MF transform: 3x3 in the first nine numbers (row vectors), then the
/// translation.
type Affine = [f64; 12];
const IDENTITY: Affine = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];

fn apply(m: &Affine, p: [f64; 3]) -> [f64; 3] {
    let [m00, m01, m02, m10, m11, m12, m20, m21, m22, tx, ty, tz] = *m;
    [
        p[0] * m00 + p[1] * m10 + p[2] * m20 + tx,
        p[0] * m01 + p[1] * m11 + p[2] * m21 + ty,
        p[0] * m02 + p[1] * m12 + p[2] * m22 + tz,
    ]
}

/// `a` then `b` (a point goes through `a` first).
fn compose(a: &Affine, b: &Affine) -> Affine {
    let row = |r: [f64; 3], with_t: bool| {
        let mut v = apply(b, r);
        if !with_t {
            let t = apply(b, [0.0; 3]);
            v = [v[0] - t[0], v[1] - t[1], v[2] - t[2]];
        }
        v
    };
    let [m00, m01, m02, m10, m11, m12, m20, m21, m22, tx, ty, tz] = *a;
    let r0 = row([m00, m01, m02], false);
    let r1 = row([m10, m11, m12], false);
    let r2 = row([m20, m21, m22], false);
    let t = row([tx, ty, tz], true);
    [
        r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2], t[0], t[1], t[2],
    ]
}

fn parse_transform(text: &str) -> Result<Affine, MeshIoError> {
    let nums: Vec<f64> = text
        .split_whitespace()
        .map(|t| t.parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad(format!("transform `{text}` is not 12 numbers")))?;
    let m: Affine = nums
        .try_into()
        .map_err(|_| bad(format!("transform `{text}` is not 12 numbers")))?;
    if m.iter().any(|x| !x.is_finite()) {
        return Err(bad(format!("transform `{text}` is not finite")));
    }
    Ok(m)
}

/// Metres per model unit of a 3MF `unit` attribute.
fn unit_scale(unit: &str) -> Result<f64, MeshIoError> {
    Ok(match unit {
        "micron" => 1e-6,
        "millimeter" => 1e-3,
        "centimeter" => 1e-2,
        "inch" => 0.0254,
        "foot" => 0.3048,
        "meter" => 1.0,
        other => return Err(bad(format!("unknown model unit `{other}`"))),
    })
}

/// The package's model part: the target of the 3D model relationship, or
/// `3D/3dmodel.model`.
fn model_text(bytes: &[u8]) -> Result<String, MeshIoError> {
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes))
        .map_err(|e| bad(format!("not a 3MF package (zip): {e}")))?;
    let mut read = |name: &str| -> Result<Option<String>, MeshIoError> {
        let mut f = match zip.by_name(name) {
            Ok(f) => f,
            Err(zip::result::ZipError::FileNotFound) => return Ok(None),
            Err(e) => return Err(bad(format!("{name}: {e}"))),
        };
        if f.size() > MAX_MODEL_BYTES {
            return Err(bad(format!("{name} is larger than 1 GiB")));
        }
        let mut text = String::new();
        f.by_ref()
            .take(MAX_MODEL_BYTES)
            .read_to_string(&mut text)
            .map_err(|e| bad(format!("{name}: {e}")))?;
        Ok(Some(text))
    };
    let target = read("_rels/.rels")?
        .and_then(|rels| {
            let mut r = quick_xml::Reader::from_str(&rels);
            loop {
                match r.read_event() {
                    Ok(quick_xml::events::Event::Empty(e) | quick_xml::events::Event::Start(e))
                        if e.local_name().as_ref() == b"Relationship" =>
                    {
                        let attr = |k: &[u8]| {
                            e.attributes()
                                .flatten()
                                .find(|a| a.key.local_name().as_ref() == k)
                                .and_then(|a| a.unescape_value().ok().map(|v| v.into_owned()))
                        };
                        if attr(b"Type").is_some_and(|t| t.ends_with("/3dmodel")) {
                            return attr(b"Target");
                        }
                    }
                    Ok(quick_xml::events::Event::Eof) | Err(_) => return None,
                    _ => {}
                }
            }
        })
        .map(|t| t.trim_start_matches('/').to_owned())
        .unwrap_or_else(|| MODEL_PATH.to_owned());
    read(&target)?.ok_or_else(|| bad(format!("the package has no model part {target}")))
}

/// Reads a 3MF package into one mesh in metres: every build item (with
/// its transform and its components') flattened, each item's triangles
/// tagged with its index (0-based) as their source.
pub fn read_3mf(bytes: &[u8]) -> Result<TriMesh, MeshIoError> {
    let text = model_text(bytes)?;
    let (unit, objects, items) = parse_model(&text)?;
    let mut out = TriMesh::default();
    for (k, (id, m)) in items.iter().enumerate() {
        let before = out.triangles.len();
        flatten(&objects, *id, m, 0, &mut out)?;
        let added = out.triangles.len() - before;
        out.tri_source.resize(before, 0);
        out.tri_source.extend(std::iter::repeat_n(k as u32, added));
    }
    if out.triangles.is_empty() {
        return Err(MeshIoError::Empty);
    }
    for p in &mut out.positions {
        *p = p.map(|x| x * unit + 0.0);
        if p.iter().any(|x| !x.is_finite()) {
            return Err(bad("a vertex is not finite once placed"));
        }
    }
    out.weld_exact();
    Ok(out)
}

fn flatten(
    objects: &BTreeMap<u32, Object>,
    id: u32,
    m: &Affine,
    depth: usize,
    out: &mut TriMesh,
) -> Result<(), MeshIoError> {
    if depth > MAX_DEPTH {
        return Err(bad(format!(
            "components nest deeper than {MAX_DEPTH} (a cycle?)"
        )));
    }
    match objects.get(&id) {
        None => Err(bad(format!(
            "an item or component names object {id}, which does not exist"
        ))),
        Some(Object::Mesh(mesh)) => {
            if out.triangles.len() + mesh.triangles.len() > MAX_TRIANGLES {
                return Err(bad("the build has more than 100 million triangles"));
            }
            let base = out.positions.len() as u32;
            out.positions
                .extend(mesh.positions.iter().map(|p| apply(m, *p)));
            out.triangles
                .extend(mesh.triangles.iter().map(|t| t.map(|i| i + base)));
            Ok(())
        }
        Some(Object::Components(parts)) => {
            for (child, t) in parts {
                flatten(objects, *child, &compose(t, m), depth + 1, out)?;
            }
            Ok(())
        }
    }
}

type Parsed = (f64, BTreeMap<u32, Object>, Vec<(u32, Affine)>);
/// The object being read: its id, mesh and components.
type Reading = (u32, TriMesh, Vec<(u32, Affine)>);

fn parse_model(text: &str) -> Result<Parsed, MeshIoError> {
    use quick_xml::events::Event;
    let mut r = quick_xml::Reader::from_str(text);
    let mut unit = 1e-3;
    let mut objects = BTreeMap::new();
    let mut items = Vec::new();
    let mut current: Option<Reading> = None;
    loop {
        let pos = r.buffer_position() as usize;
        let at = |m: String| MeshIoError::BadData {
            offset: pos,
            message: format!("in the model part: {m}"),
        };
        let event = r.read_event().map_err(|e| at(e.to_string()))?;
        let e = match &event {
            Event::Start(e) | Event::Empty(e) => e.clone(),
            Event::End(e) if e.local_name().as_ref() == b"object" => {
                if let Some((id, mesh, comps)) = current.take() {
                    let obj = if comps.is_empty() {
                        Object::Mesh(mesh)
                    } else {
                        Object::Components(comps)
                    };
                    objects.insert(id, obj);
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let mut attrs: BTreeMap<Vec<u8>, String> = BTreeMap::new();
        for a in e.attributes() {
            let a = a.map_err(|e| at(e.to_string()))?;
            let v = a.unescape_value().map_err(|e| at(e.to_string()))?;
            attrs.insert(a.key.local_name().as_ref().to_vec(), v.into_owned());
        }
        let get = |k: &str| attrs.get(k.as_bytes()).map(String::as_str);
        let num = |k: &str| -> Result<f64, MeshIoError> {
            let v = get(k).ok_or_else(|| at(format!("missing attribute {k}")))?;
            let x: f64 = v
                .trim()
                .parse()
                .map_err(|_| at(format!("{k}=`{v}` is not a number")))?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(at(format!("{k}=`{v}` is not finite")))
            }
        };
        let index = |k: &str| -> Result<u32, MeshIoError> {
            let v = get(k).ok_or_else(|| at(format!("missing attribute {k}")))?;
            v.trim()
                .parse()
                .map_err(|_| at(format!("{k}=`{v}` is not an index")))
        };
        match e.local_name().as_ref() {
            b"model" => {
                if let Some(u) = get("unit") {
                    unit = unit_scale(u).map_err(|e| at(e.to_string()))?;
                }
            }
            b"object" => {
                let id = index("id")?;
                if matches!(event, Event::Empty(_)) {
                    continue;
                }
                current = Some((id, TriMesh::default(), Vec::new()));
            }
            b"vertex" => {
                let Some((_, mesh, _)) = current.as_mut() else {
                    return Err(at("a vertex outside an object".into()));
                };
                mesh.positions.push([num("x")?, num("y")?, num("z")?]);
            }
            b"triangle" => {
                let Some((_, mesh, _)) = current.as_mut() else {
                    return Err(at("a triangle outside an object".into()));
                };
                let t = [index("v1")?, index("v2")?, index("v3")?];
                let n = mesh.positions.len();
                if let Some(&v) = t.iter().find(|&&v| v as usize >= n) {
                    return Err(at(format!(
                        "triangle vertex {v} is out of range (the object has {n} vertices before it)"
                    )));
                }
                mesh.triangles.push(t);
            }
            b"component" => {
                let Some((_, _, comps)) = current.as_mut() else {
                    return Err(at("a component outside an object".into()));
                };
                let t = get("transform").map_or(Ok(IDENTITY), parse_transform)?;
                comps.push((index("objectid")?, t));
            }
            b"item" => {
                let t = get("transform").map_or(Ok(IDENTITY), parse_transform)?;
                items.push((index("objectid")?, t));
            }
            _ => {}
        }
    }
    if items.is_empty() {
        return Err(bad(
            "the build has no items (readers drop objects without one)",
        ));
    }
    Ok((unit, objects, items))
}

#[cfg(test)]
#[allow(clippy::indexing_slicing)]
mod tests {
    use super::*;
    use crate::mesh::test_meshes::tetra;
    use crate::mesh::{at_precision_in, validate, FileUnit, Precision};

    fn two_tetras() -> TriMesh {
        let mut a = tetra();
        a.set_source(1);
        let mut b = tetra();
        b.transform(&glam::DAffine3::from_translation(glam::DVec3::new(
            0.05, 0.0, 0.0,
        )));
        b.set_source(2);
        a.append(&b);
        at_precision_in(&a, Precision::F32, FileUnit::Millimetre)
    }

    #[test]
    fn objects_are_pieces_named_by_the_document_and_read_back_in_metres() {
        let m = two_tetras();
        let names: PartNames = [(1, "Body & <lid>".to_string()), (2, "Spout".to_string())]
            .into_iter()
            .collect();
        let mut bytes = Vec::new();
        write_3mf(&m, &names, &mut bytes).unwrap();
        let text = model_text(&bytes).unwrap();
        assert!(text.contains(r#"unit="millimeter""#), "{text}");
        assert!(text.contains(r#"name="Body &amp; &lt;lid&gt;""#), "{text}");
        assert!(text.contains(r#"name="Spout""#), "{text}");
        assert_eq!(text.matches("<item ").count(), 2);
        let back = read_3mf(&bytes).unwrap();
        // Bit for bit the validated mesh (same float32 millimetres).
        let mut want = m.positions.clone();
        let mut got = back.positions.clone();
        want.sort_by(|a, b| a.partial_cmp(b).unwrap());
        got.sort_by(|a, b| a.partial_cmp(b).unwrap());
        assert_eq!(got, want);
        let r = validate(&back, &Default::default());
        assert!(r.is_closed_manifold(), "{}", r.problems());
        assert_eq!(r.components, 2);
        assert!((r.signed_volume - validate(&m, &Default::default()).signed_volume).abs() < 1e-15);
    }

    #[test]
    fn units_transforms_and_components_are_honoured() {
        let model = r#"<?xml version="1.0"?>
<model unit="inch" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">
 <resources>
  <object id="1" type="model"><mesh><vertices>
   <vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/><vertex x="0" y="1" z="0"/><vertex x="0" y="0" z="1"/>
  </vertices><triangles>
   <triangle v1="0" v2="2" v3="1"/><triangle v1="0" v2="1" v3="3"/><triangle v1="0" v2="3" v3="2"/><triangle v1="1" v2="2" v3="3"/>
  </triangles></mesh></object>
  <object id="2" type="model"><components><component objectid="1" transform="2 0 0 0 2 0 0 0 2 10 0 0"/></components></object>
 </resources>
 <build><item objectid="2" transform="1 0 0 0 1 0 0 0 1 0 0 5"/></build>
</model>"#;
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let o = zip::write::SimpleFileOptions::default();
        zip.start_file("3D/3dmodel.model", o).unwrap();
        zip.write_all(model.as_bytes()).unwrap();
        let bytes = zip.finish().unwrap().into_inner();
        let m = read_3mf(&bytes).unwrap();
        let (lo, hi) = m.bbox().unwrap();
        let inch = 0.0254;
        assert!(
            (lo - glam::DVec3::new(10.0, 0.0, 5.0) * inch).length() < 1e-12,
            "{lo}"
        );
        assert!(
            (hi - glam::DVec3::new(12.0, 2.0, 7.0) * inch).length() < 1e-12,
            "{hi}"
        );
    }

    #[test]
    fn hostile_packages_are_refused() {
        assert!(read_3mf(b"not a zip").is_err());
        let pack = |model: &str| {
            let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
            zip.start_file("3D/3dmodel.model", zip::write::SimpleFileOptions::default())
                .unwrap();
            zip.write_all(model.as_bytes()).unwrap();
            zip.finish().unwrap().into_inner()
        };
        let cycle = r#"<model><resources><object id="1"><components><component objectid="1"/></components></object></resources><build><item objectid="1"/></build></model>"#;
        let e = read_3mf(&pack(cycle)).unwrap_err();
        assert!(e.to_string().contains("nest deeper"), "{e}");
        let oob = r#"<model><resources><object id="1"><mesh><vertices><vertex x="0" y="0" z="0"/></vertices><triangles><triangle v1="0" v2="0" v3="7"/></triangles></mesh></object></resources><build><item objectid="1"/></build></model>"#;
        let e = read_3mf(&pack(oob)).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        let nan = r#"<model><resources><object id="1"><mesh><vertices><vertex x="NaN" y="0" z="0"/></vertices></mesh></object></resources><build><item objectid="1"/></build></model>"#;
        assert!(read_3mf(&pack(nan)).is_err());
        let missing =
            r#"<model><resources></resources><build><item objectid="4"/></build></model>"#;
        assert!(read_3mf(&pack(missing)).is_err());
        let no_items = r#"<model><resources></resources><build></build></model>"#;
        assert!(read_3mf(&pack(no_items)).is_err());
    }
}
