//! Bad input is rejected up front (docs/reference/scene-format.md, "Commands"): `signorini run` exits
//! with code 1, prints one short error on stderr that names the offending entry
//! or key, and writes nothing, not even the output directory. One module a
//! topic: the scene's entries, the sweep of malformed and oversized scenes,
//! and the inputs a hostile sweep found mishandled (problem files, options).

mod scene;
