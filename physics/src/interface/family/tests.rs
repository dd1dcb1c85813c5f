//! The tests of the family declarations.

use super::*;

/// Every family says what it is, and every parameter its symbol, unit and meaning; a
/// number's default lies in its range (min ≤ default ≤ max, an open end excluded) and in the
/// editor's span; rows say what the family requires of them.
#[test]
fn every_parameter_is_documented_and_its_default_admissible() {
    for f in families() {
        assert!(!f.label.is_empty(), "{}", f.key);
        assert!(!f.description.is_empty(), "{}: no DESCRIPTION", f.key);
        for (i, p) in f.params.iter().enumerate() {
            let at = format!("{}.{}", f.key, p.key);
            assert!(!p.symbol.is_empty(), "{at}: no symbol");
            assert!(!p.unit.is_empty(), "{at}: no unit (– if dimensionless)");
            assert!(!p.meaning.is_empty(), "{at}: no meaning");
            assert!(f.params[..i].iter().all(|q| q.key != p.key), "{at} twice");
            match p.kind {
                ParamKind::Number(n) => {
                    let (r, d) = (n.range, n.default);
                    assert!(r.min <= d && d <= r.max, "{at}: default {d} outside {r}");
                    assert!(r.contains(d), "{at}: default {d} not {r}");
                    assert!(
                        n.typical[0] <= d && d <= n.typical[1],
                        "{at}: default {d} outside the editor's span {:?}",
                        n.typical
                    );
                }
                ParamKind::Points { default } => {
                    assert!(default.len() >= 2, "{at}: default rows");
                    assert!(!p.note.is_empty(), "{at}: what the rows must be");
                }
            }
        }
    }
}

/// The defaults build (the explorer's starting law), and an optional parameter left out
/// builds the same law as its default given.
#[test]
fn defaults_build_and_optional_parameters_take_them() {
    for f in families() {
        let law = f
            .build(&f.defaults())
            .unwrap_or_else(|e| panic!("{}: {e:?}", f.key));
        for p in f.params.iter().filter(|p| p.optional) {
            let mut values = f.defaults();
            values.0.remove(p.key);
            assert_eq!(f.build(&values).as_ref(), Ok(&law), "{}.{}", f.key, p.key);
        }
    }
}

/// A number just outside its range is refused, the error naming the key.
#[test]
fn a_number_outside_its_range_is_refused() {
    for f in families() {
        for p in f.params {
            let ParamKind::Number(n) = p.kind else {
                continue;
            };
            let r = n.range;
            let below = if r.min_open { r.min } else { r.min - 1.0 };
            let values = f.defaults().with(p.key, below);
            let e = f
                .build(&values)
                .expect_err(&format!("{}.{} = {below}", f.key, p.key));
            assert_eq!(e.key, p.key, "{}", f.key);
        }
    }
}
