//! The 2D cut-pattern piece: sew line, cut line (seam allowance), notches, grain, labels,
//! material shrink, and the layout of pieces on a sheet.
