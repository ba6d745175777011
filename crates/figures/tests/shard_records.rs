//! Shard records and specs through the crate's public API: a record decodes to itself bit for
//! bit, shards cover every job once, and a bad spec is refused with the form. (Integration tests
//! rather than unit tests: the crate's library is then not compiled a second time in test mode,
//! which cost 48 CPU-s of CI's build.)

use rollphase_figures::analysis::orbits::sphere_orbits::Settlement;
use rollphase_figures::figures::shard::{Fields, Record, ShardSpec, decode_line, encode_line};
use rollphase_figures::glam::DVec3;

fn round_trip<T: Record + PartialEq + std::fmt::Debug>(x: T) {
    let mut v = Vec::new();
    x.encode(&mut v);
    let line = encode_line(&v);
    let back = decode_line(&line).expect("numbers");
    assert_eq!(
        back.iter().map(|f| f.to_bits()).collect::<Vec<_>>(),
        v.iter().map(|f| f.to_bits()).collect::<Vec<_>>()
    );
    let mut fields = Fields::of(&back);
    assert_eq!(T::decode(&mut fields).expect("decodes"), x);
    assert_eq!(fields.remaining(), 0);
}

#[test]
fn records_round_trip_bit_for_bit() {
    round_trip(0.1f64 + 0.2);
    round_trip(-0.0f64);
    round_trip(f64::MIN_POSITIVE / 3.0);
    round_trip(f64::INFINITY);
    round_trip(Some((DVec3::new(1e-300, -2.5, 1.0 / 3.0), 7.25)));
    round_trip(None::<(DVec3, f64)>);
    round_trip(u64::MAX - 2);
    round_trip((true, 3usize, vec![vec![1.5f64], vec![]]));
    round_trip(vec![
        Settlement::Halts { t: 12.5 },
        Settlement::Periodic {
            period: 9.87654321,
            k: 2,
            point: [0.6, -0.8, 1e-17],
            t: 1999.9,
        },
        Settlement::Undecided { omega_end: 3e-4 },
    ]);
    // NaN compares unequal, so check its bits directly.
    let line = encode_line(&[f64::NAN, f64::NEG_INFINITY]);
    let back = decode_line(&line).expect("numbers");
    assert!(back[0].is_nan() && back[1] == f64::NEG_INFINITY);
}

#[test]
fn shards_cover_every_job_once_in_order() {
    for n in [0, 1, 7, 100, 9001] {
        for count in [1, 2, 3, 8, 13] {
            let mut next = 0;
            for index in 1..=count {
                let r = ShardSpec { index, count }.range(n);
                assert_eq!(r.start, next);
                assert!(r.len() <= n / count + 1);
                next = r.end;
            }
            assert_eq!(next, n);
        }
    }
}

#[test]
fn bad_shard_specs_are_refused_with_the_form() {
    for bad in ["0/4", "5/4", "1/0", "a/b", "3", "-1/2", "1/200000"] {
        let e = bad.parse::<ShardSpec>().expect_err(bad);
        assert!(e.contains("I/N"), "{bad}: {e}");
    }
    assert_eq!(
        "3/8".parse::<ShardSpec>(),
        Ok(ShardSpec { index: 3, count: 8 })
    );
}
