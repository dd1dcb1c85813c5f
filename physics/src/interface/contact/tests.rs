//! The tests of the stage-7 contact formulas at one node.

use super::*;

/// A deterministic pseudo-random number in [−1, 1).
fn rnd(k: &mut u64) -> f64 {
    *k = k
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*k >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

fn unit(x: [f64; 3]) -> [f64; 3] {
    let l = norm(x);
    x.map(|c| c / l)
}

/// With every component free, the law of model §3.4 written out by hand.
#[test]
fn all_free_is_the_free_law() {
    let mut k = 7;
    for _ in 0..200 {
        let n = unit([rnd(&mut k), rnd(&mut k), rnd(&mut k)]);
        let v0 = [rnd(&mut k), rnd(&mut k), rnd(&mut k)];
        let vp = [0.1 * rnd(&mut k), 0.0, 0.2];
        let mu = 0.5 * (1.0 + rnd(&mut k));
        let (mut a, mut b) = (v0, v0);
        // Model §3.4: r_N = −m v_N, trial −m v_T, Coulomb.
        let rel = [a[0] - vp[0], a[1] - vp[1], a[2] - vp[2]];
        let vn = dot(rel, n);
        let vt = [rel[0] - vn * n[0], rel[1] - vn * n[1], rel[2] - vn * n[2]];
        let pn = (-2.0 * vn).max(0.0);
        let scale = if 2.0 * norm(vt) <= mu * pn {
            2.0
        } else {
            mu * pn / norm(vt)
        };
        let pa: [f64; 3] = std::array::from_fn(|c| pn * n[c] - scale * vt[c]);
        let (pb, _) = contact_impulse(&mut b, 0.0, n, vp, mu, 2.0, [true; 3], None);
        for c in 0..3 {
            assert!(
                (pa[c] - pb[c]).abs() <= 1e-14 * (1.0 + norm(pa)),
                "{pa:?} {pb:?}"
            );
            a[c] += pa[c] / 2.0;
            assert!((a[c] - b[c]).abs() <= 1e-14 * (1.0 + norm(a)));
        }
    }
}

/// Frictionless, one or two components prescribed, a tilted normal: the velocity after the
/// impulse is Moreau's, the point of {V ∈ V* + F : n·(V − v_plane) ≥ 0} nearest to V*
/// (Gauss's least constraint with a lumped mass). Checked against 2000 random feasible
/// points of that set, none nearer; and the prescribed components are untouched.
#[test]
fn frictionless_is_the_least_constraint_velocity_on_the_free_components() {
    let mut k = 11;
    for free in [
        [true, true, false],
        [false, true, true],
        [true, false, false],
    ] {
        for _ in 0..50 {
            let n = unit([rnd(&mut k), rnd(&mut k), 1.0 + rnd(&mut k).abs()]);
            let v0 = [rnd(&mut k), rnd(&mut k), -1.0 + 0.5 * rnd(&mut k)];
            let vp = [0.0, 0.1, 0.0];
            let mut v = v0;
            let (p, _) = contact_impulse(&mut v, -1e-9, n, vp, 0.0, 3.0, free, None);
            let rel = |x: [f64; 3]| dot([x[0] - vp[0], x[1] - vp[1], x[2] - vp[2]], n);
            for c in 0..3 {
                if !free[c] {
                    assert_eq!((v[c], p[c]), (v0[c], 0.0));
                }
            }
            let dist = |x: [f64; 3]| norm([x[0] - v0[0], x[1] - v0[1], x[2] - v0[2]]);
            if rel(v0) >= 0.0 {
                assert_eq!(v, v0);
                continue;
            }
            assert!(rel(v).abs() <= 1e-12, "approach velocity left: {}", rel(v));
            for _ in 0..2000 {
                let d: [f64; 3] =
                    std::array::from_fn(|c| if free[c] { 3.0 * rnd(&mut k) } else { 0.0 });
                let x = [v0[0] + d[0], v0[1] + d[1], v0[2] + d[2]];
                if rel(x) >= 0.0 {
                    assert!(dist(x) >= dist(v) - 1e-12);
                }
            }
        }
    }
}

/// A symmetry edge (x prescribed) on a plane z = 0 sliding along y with x held: stick when
/// μ allows it (no free relative velocity left), else slip on the cone |r_T| = μλ against
/// the free sliding velocity; the normal along a prescribed axis gives no impulse.
#[test]
fn friction_in_the_free_tangent_plane() {
    let n = [0.0, 0.0, 1.0];
    let free = [false, true, true];
    let mut v = [0.3, 0.2, -1.0];
    let (p, s) = contact_impulse(&mut v, 0.0, n, [0.0; 3], 0.5, 1.0, free, None);
    assert_eq!((s, v), (ContactStatus::Stick, [0.3, 0.0, 0.0]));
    assert_eq!(p, [0.0, -0.2, 1.0]);
    let mut v = [0.3, 0.8, -1.0];
    let (p, s) = contact_impulse(&mut v, 0.0, n, [0.0; 3], 0.5, 1.0, free, None);
    assert_eq!(s, ContactStatus::Slip);
    assert_eq!(p, [0.0, -0.5, 1.0]);
    assert!((v[1] - 0.3).abs() < 1e-15 && v[2] == 0.0);
    let mut v = [0.3, 0.8, -1.0];
    let (p, s) = contact_impulse(
        &mut v,
        0.0,
        n,
        [0.0; 3],
        0.5,
        1.0,
        [true, true, false],
        None,
    );
    assert_eq!((p, s, v), ([0.0; 3], ContactStatus::Open, [0.3, 0.8, -1.0]));
}

/// A held contact with an open gap g: approaching faster than g/h it is brought to
/// v_N = −g/h exactly (it arrives on the surface at the next position), friction in the
/// cone of that impulse; approaching slower, or leaving, it is open. A first contact at
/// the same gap is open whatever its velocity (eq. 19 at gₙ₊₁ ≤ 0 alone).
#[test]
fn a_held_contact_closes_its_gap_in_one_step_and_no_more() {
    let (n, vp, m, h, g) = ([0.0, 0.0, 1.0], [0.0, 0.5, 0.0], 2.0, 1e-3, 4e-6);
    let mut v = [0.0, 0.5, -29.0];
    let (p, s) = contact_impulse(&mut v, g, n, vp, 0.0, m, [true; 3], Some(h));
    assert_eq!(s, ContactStatus::Stick);
    assert!((v[2] + g / h).abs() <= 1e-15 * 29.0, "v_N {}", v[2]);
    assert_eq!(p[2], m * (-g / h + 29.0));
    let mut v = [20.0, 0.5, -29.0];
    let (p, s) = contact_impulse(&mut v, g, n, vp, 0.3, m, [true; 3], Some(h));
    assert_eq!(s, ContactStatus::Slip);
    assert!((norm([p[0], p[1], 0.0]) - 0.3 * p[2]).abs() <= 1e-12 * p[2]);
    for vz in [-0.5 * g / h, 0.0, 3.0] {
        let mut v = [0.1, 0.5, vz];
        let (p, s) = contact_impulse(&mut v, g, n, vp, 0.3, m, [true; 3], Some(h));
        assert_eq!((p, s, v), ([0.0; 3], ContactStatus::Open, [0.1, 0.5, vz]));
    }
    let mut v = [0.1, 0.5, -29.0];
    let (p, s) = contact_impulse(&mut v, g, n, vp, 0.3, m, [true; 3], None);
    assert_eq!(
        (p, s, v),
        ([0.0; 3], ContactStatus::Open, [0.1, 0.5, -29.0])
    );
}
