//! SDF CSG from a component library (paper 2, EasyVRModeling §3–5).

pub mod mc;

#[cfg(test)]
mod tests;
