mod library;
mod mc;
mod mesh_sdf;
mod scenes;
mod volume;
