//! Writers of cut patterns: SVG, PNG, EXR, DXF (AAMA/ASTM D6673), tiled PDF, GLB colour maps.
//! They produce bytes; the caller writes files (atomically).
