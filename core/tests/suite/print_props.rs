//! Random mixed documents through the printable path (issue 17): every
//! kind of object (solids, GC assemblies, SDF volumes, closed and open
//! curve networks, an unfinished network, sculpt meshes), placed at random
//! with touching, duplicated-in-place and nearly coincident parts. Every
//! result must be a mesh that, written as binary STL and read back, passes
//! our checks (closed, oriented, embedded, at float32) and Manifold's import
//! (`manifold-rust`, byte-identical to `manifold3d`); otherwise a typed
//! error. Zero bad files.
//!
//! Documents are built from a library of evaluated objects, each placed
//! by a rigid transform of its mesh: exactly what an object placement
//! does, without replaying the objects' ops for every document.
//! `SHAPEWRIGHT_PRINT_DOCS=N` runs N documents (default 300, what CI runs;
//! `scripts/print_soak.sh` runs more) and prints the count of refusals by
//! reason.

use shapewright::math::fm::DetMath as _;
use std::collections::BTreeMap;
use std::path::Path;

use glam::{DAffine3, DQuat, DVec3};
use shapewright::doc::{parse_script, run_script, ObjectKind, OpLog};
use shapewright::mesh::{
    manifold_accepts, read_stl, validate, write_stl, TriMesh, ValidationSettings,
};
use shapewright::print::{printable, PrintError, PrintPart, PrintSettings};

/// SplitMix64: a small deterministic generator (the seed names the case).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// One library object: its kind's name, whether it is a surface, its mesh.
struct Item {
    name: String,
    kind: &'static str,
    surface: bool,
    mesh: TriMesh,
}

fn script(text: &str) -> OpLog {
    let lines = parse_script(text).unwrap_or_else(|e| panic!("{e}"));
    let mut log = OpLog::new();
    run_script(&mut log, &lines).unwrap_or_else(|e| panic!("{e}"));
    log
}

fn library() -> Vec<Item> {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    let mut items = Vec::new();
    let mut add_log = |name: &str, log: &OpLog| {
        for (_, obj) in log.document().objects() {
            items.push(Item {
                name: name.to_string(),
                kind: obj.kind.name(),
                surface: matches!(obj.kind, ObjectKind::CurveNetwork(_)),
                mesh: (*obj.mesh).clone(),
            });
        }
    };
    for f in [
        "mug.jsonl",
        "table.jsonl",
        "vase.jsonl",
        "funnel.jsonl",
        "hammer.jsonl",
        "csg_cup.jsonl",
        "csg_pedestal.jsonl",
        "curve_network.jsonl",
        "lampshade.jsonl",
        "primitives.jsonl",
    ] {
        let text = std::fs::read_to_string(data.join(f)).unwrap();
        add_log(f, &script(&text));
    }
    let extra = [
        // A sculpt sphere pulled by one gentle stroke.
        "{\"op\":\"sculpt_create\",\"base\":{\"kind\":\"sphere\",\"radius\":0.08,\"edge_length\":0.012}}\n\
         {\"op\":\"sculpt_stroke\",\"id\":1,\"settings\":{\"brush\":{\"kind\":\"sphere\",\"radius\":0.05},\"brush_scale\":1.0,\"influence\":0.5,\"falloff\":\"smooth\",\"warp\":{\"kind\":\"drag\"},\"max_edge_rel\":0.2,\"min_edge_rel\":0.05},\"samples\":[\
         {\"position\":[0,0,0.08],\"rotation\":[0,0,0,1],\"pressure\":1},{\"position\":[0,0,0.09],\"rotation\":[0,0,0,1],\"pressure\":1},\
         {\"position\":[0,0,0.1],\"rotation\":[0,0,0,1],\"pressure\":1}]}",
        // An unfinished network: curves, no patch.
        "{\"op\":\"curve_network_create\",\"resolution\":8,\"surface_n\":4}\n\
         {\"op\":\"curve_draw\",\"id\":1,\"samples\":[[-0.1,0,0],[-0.03,0.01,0],[0.03,0.01,0],[0.1,0,0]],\"fit\":{\"mode\":\"interpolate\"},\"resample\":null,\"snap_tol\":0.002}",
        // Boxes, for exact face contact.
        "{\"op\":\"add_solid\",\"shape\":{\"kind\":\"box\",\"size\":[0.1,0.1,0.1]}}\n\
         {\"op\":\"add_solid\",\"shape\":{\"kind\":\"box\",\"size\":[0.05,0.1,0.02]}}",
    ];
    for (k, text) in extra.iter().enumerate() {
        add_log(&format!("extra{k}"), &script(text));
    }
    items
}

fn random_rotation(rng: &mut Rng) -> DQuat {
    let v = DVec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    );
    DQuat::from_axis_angle(v.try_normalize().unwrap_or(DVec3::Z), rng.range(0.0, 6.3))
}

/// A document: meshes placed, with a description for failure messages.
fn random_document(lib: &[Item], seed: u64) -> (Vec<(usize, TriMesh)>, Vec<String>) {
    let mut rng = Rng(seed);
    let count = 1 + rng.below(4);
    let mut placed: Vec<(usize, TriMesh, DAffine3)> = Vec::new();
    let mut what = Vec::new();
    for _ in 0..count {
        let choice = rng.below(10);
        if choice < 2 && !placed.is_empty() {
            // Duplicated in place, or nearly coincident with an earlier part.
            let k = rng.below(placed.len());
            let (item, mesh, at) = placed[k].clone();
            let mut m = mesh.clone();
            let mut t = at;
            if choice == 1 {
                let d = 10f64.fpowf(rng.range(-9.0, -4.0));
                let dir = DVec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                )
                .normalize_or(DVec3::X);
                let shift = DAffine3::from_translation(dir * d);
                m.transform(&shift);
                t = shift * t;
                what.push(format!("{} moved {d:.1e} from part {k}", lib[item].name));
            } else {
                what.push(format!(
                    "{} duplicated in place of part {k}",
                    lib[item].name
                ));
            }
            placed.push((item, m, t));
            continue;
        }
        let item = rng.below(lib.len());
        let mut m = lib[item].mesh.clone();
        let rot = if rng.below(3) == 0 {
            random_rotation(&mut rng)
        } else {
            DQuat::IDENTITY
        };
        let mut at = DVec3::new(
            rng.range(-0.15, 0.15),
            rng.range(-0.15, 0.15),
            rng.range(-0.05, 0.1),
        );
        if choice == 2 && !placed.is_empty() && rot == DQuat::IDENTITY {
            // Touching: against an earlier part's box, along x.
            let (k_item, k_mesh, _) = &placed[placed.len() - 1];
            let _ = k_item;
            if let (Some((_, hi)), Some((lo, _))) = (k_mesh.bbox(), m.bbox()) {
                at = DVec3::new(hi.x - lo.x, 0.0, 0.0);
            }
            what.push(format!("{} touching the previous part", lib[item].name));
        } else {
            what.push(format!("{} at {at:.3} rot {rot:.3}", lib[item].name));
        }
        let t = DAffine3::from_rotation_translation(rot, at);
        m.transform(&t);
        placed.push((item, m, t));
    }
    (placed.into_iter().map(|(i, m, _)| (i, m)).collect(), what)
}

fn reason(e: &PrintError) -> &'static str {
    match e {
        PrintError::Settings { .. } => "settings",
        PrintError::Empty { .. } => "empty",
        PrintError::NonFinite { .. } => "non-finite",
        PrintError::OutOfRange { .. } => "out of range",
        PrintError::NotSolid { .. } => "not solid",
        PrintError::Thicken { .. } => "thicken",
        PrintError::SelfIntersecting { .. } => "self-intersecting",
        PrintError::Union { .. } => "union failed",
        PrintError::Invalid { .. } => "invalid at float32",
        PrintError::Cancelled => "cancelled",
    }
}

#[test]
fn random_mixed_documents_print_valid_files_or_refuse_with_a_type() {
    let docs: u64 = std::env::var("SHAPEWRIGHT_PRINT_DOCS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let first: u64 = std::env::var("SHAPEWRIGHT_PRINT_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let lib = library();
    let mut refusals: BTreeMap<&'static str, usize> = BTreeMap::new();
    let mut examples: BTreeMap<&'static str, String> = BTreeMap::new();
    let mut printed = 0usize;
    for seed in first..first + docs {
        let (parts, what) = random_document(&lib, seed);
        let print_parts: Vec<PrintPart> = parts
            .iter()
            .enumerate()
            .map(|(k, (item, mesh))| PrintPart {
                id: k as u32 + 1,
                kind: lib[*item].kind,
                surface: lib[*item].surface,
                mesh,
            })
            .collect();
        match printable(&print_parts, &PrintSettings::default()) {
            Ok(p) => {
                let mut bytes = Vec::new();
                write_stl(&p.mesh, &mut bytes).unwrap();
                let back = read_stl(&bytes).unwrap();
                let r = validate(&back, &ValidationSettings::default());
                assert!(
                    r.is_printable() && manifold_accepts(&back),
                    "seed {seed}: a bad file ({}; Manifold accepts: {})\n{what:#?}",
                    r.problems(),
                    manifold_accepts(&back)
                );
                printed += 1;
            }
            Err(e) => {
                let why = reason(&e);
                *refusals.entry(why).or_default() += 1;
                examples
                    .entry(why)
                    .or_insert_with(|| format!("seed {seed}: {e}\n    {what:?}"));
                // A refusal names an object (or says there is none).
                let msg = e.to_string();
                assert!(
                    msg.contains('#') || matches!(e, PrintError::Empty { .. }),
                    "seed {seed}: {msg}"
                );
            }
        }
    }
    println!("{docs} documents: {printed} printed, refusals {refusals:?}");
    for (why, ex) in &examples {
        println!("  {why}: {ex}");
    }
    // The test means something only if most documents print.
    assert!(
        printed as f64 >= 0.7 * docs as f64,
        "only {printed} of {docs} printed: {refusals:?}\n{examples:#?}"
    );
}
