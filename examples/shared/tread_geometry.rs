//! The geometry of the tread block of `scenes/tread.toml` and `scenes/tread_demould.toml`,
//! shared by the two generators that include it with `#[path]`: `examples/tread_block.rs` (the
//! block, `scenes/meshes/tread_block.msh`) and `examples/ribbed_mould.rs` (the ribbed mould
//! that formed it, `scenes/meshes/ribbed_mould.stl`). Lengths in millimetres (the scenes read
//! both files with `scale = 0.001`).
//!
//! A block 60 × 30 × 20 mm (x × y × z) with two grooves across its top, along y: trapezoidal,
//! 8 mm wide at the top, 4 mm at their floor, 8 mm deep, centred at x = 20 and 40 mm.

/// Block length (x), width (y), height (z) [mm].
pub const SIZE: [f64; 3] = [60.0, 30.0, 20.0];
/// Groove centres (x), top width, floor width, depth [mm].
pub const GROOVE_CENTRES: [f64; 2] = [20.0, 40.0];
pub const GROOVE_TOP: f64 = 8.0;
pub const GROOVE_FLOOR: f64 = 4.0;
pub const GROOVE_DEPTH: f64 = 8.0;

/// The moulded profile of the block's top in the x–z plane from x = `x0` to x = `x1` [mm]:
/// the rib tops (z = 20) and, for each groove, its wall down to the floor (z = 12), the floor
/// and the other wall back up, in increasing x.
pub fn top_profile(x0: f64, x1: f64) -> Vec<[f64; 2]> {
    let (top, floor) = (SIZE[2], SIZE[2] - GROOVE_DEPTH);
    let mut p = vec![[x0, top]];
    for c in GROOVE_CENTRES {
        p.extend([
            [c - 0.5 * GROOVE_TOP, top],
            [c - 0.5 * GROOVE_FLOOR, floor],
            [c + 0.5 * GROOVE_FLOOR, floor],
            [c + 0.5 * GROOVE_TOP, top],
        ]);
    }
    p.push([x1, top]);
    p
}
