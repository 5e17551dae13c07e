//! Second-order meshes from first-order ones (stub).
