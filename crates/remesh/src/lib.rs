//! Scan preparation: isotropic remeshing to a working resolution, decimation of huge scans,
//! hole filling; every output vertex maps back to a point of the input surface.
