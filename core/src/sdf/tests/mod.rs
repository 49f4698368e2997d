mod mc;
mod mesh_sdf;
mod volume;
