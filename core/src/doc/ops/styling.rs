//! The styling ops (paper 3): the payloads of [`crate::styling::edits`]
//! applied to a document's [`CurveNetwork`].

use super::{EditCx, ObjectCreate, ObjectEdit};
use crate::doc::OpError;
use crate::styling::{self as st, CurveNetwork};

impl ObjectCreate for st::CurveNetworkCreate {
    type Target = CurveNetwork;
    fn build(&self, _: &mut EditCx<'_>) -> Result<CurveNetwork, OpError> {
        Ok(st::CurveNetworkCreate::build(self)?)
    }
}

macro_rules! network_edits {
    ($($ty:ty => |$op:ident, $net:ident| $body:expr),* $(,)?) => {$(
        impl ObjectEdit for $ty {
            type Target = CurveNetwork;
            fn apply(&self, $net: &mut CurveNetwork, cx: &mut EditCx<'_>) -> Result<(), OpError> {
                let $op = self;
                cx.add_work($body?);
                Ok(())
            }
        }
    )*};
}

network_edits!(
    st::CurveDraw => |op, net| op.apply_to(net),
    st::CurveSmooth => |op, net| op.apply_to(net),
    st::CurveSharpen => |op, net| op.apply_to(net),
    st::CurvePull => |op, net| op.apply_to(net),
    st::CurveDelete => |op, net| op.apply_to(net),
    st::CurveFillLoop => |op, net| op.apply_to(net),
    st::CurveFillAuto => |op, net| op.apply_to(net),
    st::SurfaceSmooth => |op, net| op.0.apply_to(net, false),
    st::SurfaceSharpen => |op, net| op.0.apply_to(net, true),
    st::SurfacePull => |op, net| op.apply_to(net),
);
