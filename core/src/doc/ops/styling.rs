//! The styling ops (paper 3): the payloads of [`crate::styling::edits`]
//! applied to a document's [`CurveNetwork`].

use super::object::compose;
use super::{Apply, EditCx, ObjectCreate, ObjectEdit, OpOutcome};
use crate::doc::{Document, KindOf, OpError};
use crate::math::Transform;
use crate::styling::{self as st, CurveNetwork};

impl ObjectCreate for st::CurveNetworkCreate {
    type Target = CurveNetwork;
    fn build(&self, _: &mut EditCx<'_>) -> Result<CurveNetwork, OpError> {
        Ok(st::CurveNetworkCreate::build(self)?)
    }
}

macro_rules! network_edits {
    ($($ty:ty => |$op:ident, $net:ident, $cx:ident| $body:expr),* $(,)?) => {$(
        impl ObjectEdit for $ty {
            type Target = CurveNetwork;
            fn apply(&self, $net: &mut CurveNetwork, $cx: &mut EditCx<'_>) -> Result<(), OpError> {
                let $op = self;
                let work = $body?;
                $cx.add_work(work);
                Ok(())
            }
        }
    )*};
}

// The held surface tools stop before a crease tighter than the document's
// print wall (`set_wall_thickness`), as it is when the op applies.
network_edits!(
    st::CurveDraw => |op, net, cx| op.apply_to(net),
    st::CurveSmooth => |op, net, cx| op.apply_to(net),
    st::CurveSharpen => |op, net, cx| op.apply_to(net),
    st::CurvePull => |op, net, cx| op.apply_to(net),
    st::CurveAttract => |op, net, cx| op.apply_to(net),
    st::CurveDelete => |op, net, cx| op.apply_to(net),
    st::CurveFillLoop => |op, net, cx| op.apply_to(net),
    st::CurveFillAuto => |op, net, cx| op.apply_to(net),
    st::SurfaceSmooth => |op, net, cx| op.0.apply_to(net, false, cx.print_setup().wall_thickness),
    st::SurfaceSharpen => |op, net, cx| op.0.apply_to(net, true, cx.print_setup().wall_thickness),
    st::SurfacePull => |op, net, cx| op.apply_to(net, cx.print_setup().wall_thickness),
);

/// Drawing in the held modeling frame changes the network's curves and its
/// placement (the network moves with the frame), so it is a document op
/// rather than an [`ObjectEdit`]; both land together or not at all (the
/// log applies ops to a copy).
impl Apply for st::CurveDrawInFrame {
    const KIND: &'static str = CurveNetwork::NAME;
    fn apply(&self, doc: &mut Document) -> Result<OpOutcome, OpError> {
        let placement = doc.get(self.id)?.transform();
        let mut net = doc.get_as::<CurveNetwork>(self.id)?.clone();
        let (work, motion) = self.apply_to(&mut net, &placement.to_affine()?)?;
        doc.add_work(work);
        doc.replace(self.id, net.into_kind())?;
        if let Some((t, q)) = motion {
            let m = Transform {
                translate: t.to_array(),
                rotate: q.to_array(),
                scale: [1.0; 3],
            };
            doc.set_placement(self.id, compose(&m, &placement)?)?;
        }
        Ok(OpOutcome::default())
    }
}
