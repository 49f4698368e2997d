//! Property tests of the op log over random op sequences with interleaved
//! undo and redo (1000 cases): live state equals replay from empty, undo k
//! then redo k returns to the same hash, failing ops change nothing, and
//! every object's mesh is a closed 2-manifold.

use proptest::prelude::*;
use shapewright::doc::*;
use shapewright::math::Transform;
use shapewright::mesh::validate;
use shapewright::solid::SolidShape;

#[derive(Clone, Debug)]
enum Step {
    Op(Op),
    Undo,
    Redo,
}

fn size() -> impl Strategy<Value = f64> {
    // Mostly valid sizes, sometimes zero, negative or non-finite.
    prop_oneof![
        8 => 0.05f64..2.0,
        1 => Just(0.0),
        1 => -1.0f64..0.0,
        1 => Just(f64::NAN),
    ]
}

fn shape() -> impl Strategy<Value = SolidShape> {
    prop_oneof![
        (size(), size(), size()).prop_map(|(a, b, c)| SolidShape::Box { size: [a, b, c] }),
        size().prop_map(|radius| SolidShape::Sphere { radius }),
        (size(), size(), size()).prop_map(|(a, b, c)| SolidShape::Ellipsoid { radii: [a, b, c] }),
        (size(), size()).prop_map(|(radius, height)| SolidShape::Cylinder { radius, height }),
        (size(), size()).prop_map(|(radius, height)| SolidShape::Cone { radius, height }),
        (size(), size()).prop_map(|(major_radius, minor_radius)| SolidShape::Torus {
            major_radius,
            minor_radius
        }),
        (size(), 0.0f64..1.0).prop_map(|(radius, length)| SolidShape::Capsule { radius, length }),
    ]
}

fn transform() -> impl Strategy<Value = Transform> {
    (
        prop::array::uniform3(-2.0f64..2.0),
        prop::array::uniform4(-1.0f64..1.0),
        prop_oneof![4 => (0.2f64..3.0).prop_map(|s| [s; 3]), 1 => prop::array::uniform3(-2.0f64..2.0)],
    )
        .prop_map(|(translate, rotate, scale)| Transform { translate, rotate, scale })
}

fn step() -> impl Strategy<Value = Step> {
    let id = (0u32..7).prop_map(ObjectId);
    let segments = prop_oneof![8 => 8u32..20, 1 => 0u32..8];
    prop_oneof![
        4 => (shape(), segments.clone(), transform())
            .prop_map(|(shape, segments, transform)| Step::Op(Op::AddSolid(AddSolid { shape, segments, transform }))),
        2 => (id.clone(), shape(), segments).prop_map(|(id, shape, segments)| Step::Op(Op::EditSolid(Edit::new(id, EditSolid { shape, segments ,})))),
        2 => (id.clone(), transform()).prop_map(|(id, transform)| Step::Op(Op::SetTransform(SetTransform { id, transform }))),
        2 => (id.clone(), transform()).prop_map(|(id, transform)| Step::Op(Op::TransformBy(TransformBy { id, transform }))),
        1 => id.clone().prop_map(|id| Step::Op(Op::Duplicate(Duplicate { id }))),
        1 => id.prop_map(|id| Step::Op(Op::Delete(Delete { id }))),
        2 => Just(Step::Undo),
        2 => Just(Step::Redo),
    ]
}

fn check_meshes(doc: &Document) -> Result<(), TestCaseError> {
    for (id, obj) in doc.objects() {
        let r = validate(&obj.mesh, &Default::default());
        prop_assert!(r.is_closed_manifold(), "object {id}: {}", r.problems());
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, max_shrink_iters: 2000, ..ProptestConfig::default() })]

    #[test]
    fn random_histories_hold_the_log_invariants(steps in prop::collection::vec(step(), 1..24), k in 1usize..6) {
        let mut log = OpLog::with_policy(CheckpointPolicy { every_ops: 3, ..Default::default() });
        for s in &steps {
            let before = (log.document().content_hash(), log.len(), log.cursor());
            let result = match s {
                Step::Op(op) => log.apply(op.clone()).map(|_| ()),
                Step::Undo => log.undo(),
                Step::Redo => log.redo(),
            };
            if result.is_err() {
                prop_assert_eq!((log.document().content_hash(), log.len(), log.cursor()), before, "a failed step changed the log");
            }
            check_meshes(log.document())?;
        }
        // Live equals replay from empty, with the same redo tail.
        let replayed = OpLog::replay(log.ops().to_vec(), log.cursor()).unwrap();
        prop_assert_eq!(replayed.document().content_hash(), log.document().content_hash());
        // Undo k, redo k returns to the same state.
        let hash = log.document().content_hash();
        let k = k.min(log.cursor());
        for _ in 0..k { log.undo().unwrap(); }
        for _ in 0..k { log.redo().unwrap(); }
        prop_assert_eq!(log.document().content_hash(), hash);
    }
}
