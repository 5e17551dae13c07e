//! Gmsh .msh import (stub: filled in by the Gmsh import work).
