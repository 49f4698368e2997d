mod library;
mod mc;
mod mesh_sdf;
mod reuse_ops;
mod scenes;
mod topology;
mod volume;
