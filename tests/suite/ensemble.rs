//! Columnar ensembles (`scenes::run_ensemble`) and dotted scene fields
//! (`Scene::set`): members equal their single runs bit for bit, bad tables
//! are refused naming the column (and the member), and a member's failure
//! stays with that member.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use framedyn::scenes::{
    example, run_ensemble, Ensemble, EnsembleOptions, FlatSink, Keep, MemberStatus, Scene, Table, UserFunctions, UserPotentialFn, DEFAULT_SCENE,
};
use proptest::prelude::*;

fn single(scene: &Scene) -> FlatSink {
    let mut sim = scene.build().unwrap();
    let mut sink = FlatSink::default();
    sim.run(&mut sink, &AtomicBool::new(false), &mut |_| {}).unwrap();
    sink
}

fn ensemble(base: &Scene, table: &Table, keep: Keep, threads: Option<usize>) -> Ensemble {
    run_ensemble(base, table, &EnsembleOptions { keep, threads, oversubscribe: false }, None, &AtomicBool::new(false), &|_| {}).unwrap()
}

/// A short S² gyroscope whose members differ in initial state, body and
/// potential.
fn base() -> Scene {
    let mut s = example(DEFAULT_SCENE).unwrap();
    s.time.t_end = 1.0;
    s
}

fn bits(a: &[f64]) -> Vec<u64> {
    a.iter().map(|v| v.to_bits()).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(12))]
    /// Every member's records are those of the single run of its scene, bit
    /// for bit, whatever the thread count.
    #[test]
    fn members_equal_single_runs_bit_for_bit(
        r in prop::collection::vec(0.1f64..2.5, 1..6),
        seed in 0u64..1000,
        threads in 1usize..3,
    ) {
        let n = r.len();
        let spin: Vec<f64> = (0..n).map(|i| 0.01 * ((seed + i as u64) % 7) as f64).collect();
        let beta: Vec<f64> = (0..n).map(|i| -0.3 + 0.05 * ((seed * 3 + i as u64) % 5) as f64).collect();
        let inertia: Vec<f64> = (0..n).map(|i| 0.1 + 0.02 * i as f64).collect();
        let table = Table::new([
            ("initial.r", r.clone()),
            ("initial.spin", spin.clone()),
            ("potential.beta_hat", beta.clone()),
            ("body.inertia", inertia.clone()),
        ]).unwrap();
        let out = ensemble(&base(), &table, Keep::All, Some(threads));
        prop_assert_eq!(out.len(), n);
        for i in 0..n {
            let mut s = base();
            s.set("initial.r", r[i]).unwrap();
            s.set("initial.spin", spin[i]).unwrap();
            s.set("potential.beta_hat", beta[i]).unwrap();
            s.set("body.inertia", inertia[i]).unwrap();
            let one = single(&s);
            prop_assert_eq!(out.members[i].status, MemberStatus::Finished);
            prop_assert_eq!(bits(out.records(i)), bits(&one.data));
            prop_assert_eq!(&out.columns, &one.columns);
        }
    }
}

/// `Keep::Final` keeps the last record of `Keep::All`; `Keep::Samples(k)`
/// the records of the scene with `output.samples = k`.
#[test]
fn keep_final_and_samples() {
    let table = Table::new([("initial.r", vec![0.4, 0.8, 1.2])]).unwrap();
    let all = ensemble(&base(), &table, Keep::All, None);
    let fin = ensemble(&base(), &table, Keep::Final, None);
    let k = 7;
    let sampled = ensemble(&base(), &table, Keep::Samples(k), None);
    assert_eq!(fin.uniform_records(), Some(1));
    assert_eq!(sampled.uniform_records(), Some(k as usize));
    let nc = all.columns.len();
    for i in 0..3 {
        let a = all.records(i);
        assert_eq!(bits(fin.records(i)), bits(&a[a.len() - nc..]));
        let mut s = base();
        s.set("initial.r", table.column("initial.r").unwrap()[i]).unwrap();
        s.output.every = None;
        s.output.samples = Some(k);
        assert_eq!(bits(sampled.records(i)), bits(&single(&s).data));
        let (sa, sf) = (all.members[i].summary.as_ref().unwrap(), fin.members[i].summary.as_ref().unwrap());
        assert_eq!((sa.steps, sa.energy_drift.to_bits(), sa.max_defect.to_bits()), (sf.steps, sf.energy_drift.to_bits(), sf.max_defect.to_bits()));
    }
    let err = run_ensemble(&base(), &table, &EnsembleOptions { keep: Keep::Samples(1), ..Default::default() }, None, &AtomicBool::new(false), &|_| {}).unwrap_err();
    assert!(err.to_string().contains("samples"), "{err}");
}

/// Bad tables are refused before anything runs, naming the column and, for
/// a bad value, the first bad member.
#[test]
fn bad_tables_name_the_column_and_member() {
    let msg = |r: Result<Table, framedyn::scenes::SceneError>| r.unwrap_err().to_string();
    let e = msg(Table::new([("initial.r", vec![0.1, 0.2]), ("initial.spin", vec![0.0])]));
    assert!(e.contains("initial.spin") && e.contains("initial.r") && e.contains("2 members"), "{e}");
    let e = msg(Table::new([("initial.r", vec![0.1, f64::NAN, f64::INFINITY])]));
    assert!(e.contains("initial.r") && e.contains("member 1") && e.contains("finite"), "{e}");
    let e = msg(Table::new([("body.colour", vec![0.1])]));
    assert!(e.contains("body.colour") && e.contains("allowed"), "{e}");
    let e = msg(Table::new([("initial.r", vec![0.1]), ("initial.r", vec![0.2])]));
    assert!(e.contains("initial.r") && e.contains("once"), "{e}");
    let e = msg(Table::new(Vec::<(&str, Vec<f64>)>::new()));
    assert!(e.contains("table") && e.contains("column"), "{e}");
    let e = msg(Table::new([("initial.r", vec![])]));
    assert!(e.contains("0 members"), "{e}");
    let e = msg(Table::new([("body.J.0", vec![1.0])]));
    assert!(e.contains("body.J.0") && e.contains("two indices"), "{e}");
    let opts = EnsembleOptions { keep: Keep::All, threads: Some(0), oversubscribe: false };
    let t = Table::new([("initial.r", vec![0.5])]).unwrap();
    let e = run_ensemble(&base(), &t, &opts, None, &AtomicBool::new(false), &|_| {}).unwrap_err().to_string();
    assert!(e.contains("threads") && e.contains("1024"), "{e}");
}

/// An out-of-range value makes its member invalid (not run) with a message
/// naming the field, the column and the member; the other members run as
/// they would alone.
#[test]
fn an_invalid_member_does_not_affect_the_others() {
    let table = Table::new([("body.inertia", vec![0.2, -1.0, 0.3]), ("initial.r", vec![0.5, 0.6, 0.7])]).unwrap();
    let out = ensemble(&base(), &table, Keep::All, Some(2));
    let st: Vec<MemberStatus> = out.members.iter().map(|m| m.status).collect();
    assert_eq!(st, [MemberStatus::Finished, MemberStatus::Invalid, MemberStatus::Finished]);
    let e = out.members[1].error.as_deref().unwrap();
    assert!(e.contains("body.inertia") && e.contains("member 1") && e.contains("-1"), "{e}");
    assert_eq!(out.records(1).len(), 0);
    assert!(out.members[1].summary.is_none());
    let mut s = base();
    s.set("body.inertia", 0.3).unwrap();
    s.set("initial.r", 0.7).unwrap();
    assert_eq!(bits(out.records(2)), bits(&single(&s).data));
}

/// A member whose user potential turns non-finite fails on its own, with the
/// records up to the failure; the members around it finish.
#[test]
fn a_failing_member_keeps_its_partial_records_and_spares_the_others() {
    let mut b = base();
    let (a, bb) = (b.potential.alpha_hat.unwrap(), b.potential.beta_hat.unwrap());
    b.potential = Default::default();
    let table = Table::new([("initial.spin", vec![0.0, 0.01, 0.02, 0.03])]).unwrap();
    let calls = Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let c = calls.clone();
    let user = move |i: usize| {
        let c = c.clone();
        let value: UserPotentialFn = Arc::new(move |x: &[f64], _e: &[f64]| {
            c.fetch_add(1, Ordering::Relaxed);
            // Member 2 leaves its potential's domain once the particle is
            // above z = 0.9.
            if i == 2 && x[2] > 0.9 {
                f64::NAN
            } else {
                a * x[2] * x[2] + bb * x[2]
            }
        });
        UserFunctions { value, gradient: None }
    };
    let out = run_ensemble(&b, &table, &EnsembleOptions { keep: Keep::All, threads: Some(2), oversubscribe: false }, Some(&user), &AtomicBool::new(false), &|_| {}).unwrap();
    let st: Vec<MemberStatus> = out.members.iter().map(|m| m.status).collect();
    assert_eq!(st, [MemberStatus::Finished, MemberStatus::Finished, MemberStatus::Failed, MemberStatus::Finished]);
    let e = out.members[2].error.as_deref().unwrap();
    assert!(e.contains("member 2"), "{e}");
    let n = out.columns.len();
    let rec = out.records(2);
    assert!(rec.len() >= n, "the failed member kept no records");
    assert!(rec.iter().all(|v| v.is_finite()), "a failed member's records are its good states");
    let t_last = rec[rec.len() - n];
    assert!(t_last < b.time.t_end, "failed member reached t_end");
    assert!(calls.load(Ordering::Relaxed) > 0);
}

/// A raised cancellation flag stops every member (status `Cancelled`).
#[test]
fn cancelled_ensemble_reports_every_member() {
    let table = Table::new([("initial.r", vec![0.5; 5])]).unwrap();
    let out = run_ensemble(&base(), &table, &EnsembleOptions::default(), None, &AtomicBool::new(true), &|_| {}).unwrap();
    assert!(out.members.iter().all(|m| m.status == MemberStatus::Cancelled));
}

/// The progress callback counts every member once.
#[test]
fn progress_counts_members() {
    let table = Table::new([("initial.r", vec![0.5, 0.6, 0.7, 0.8])]).unwrap();
    let seen = std::sync::Mutex::new(Vec::new());
    run_ensemble(&base(), &table, &EnsembleOptions::default(), None, &AtomicBool::new(false), &|k| seen.lock().unwrap().push(k)).unwrap();
    let mut v = seen.into_inner().unwrap();
    v.sort();
    assert_eq!(v, [1, 2, 3, 4]);
}

/// Every kind of dotted path reaches its field; components of fields the
/// scene does not give, and indices out of range, are refused naming the
/// path.
#[test]
fn dotted_paths_set_their_fields() {
    let mut s = base();
    let mut g = base();
    g.set("manifold.radius", 2.0).unwrap();
    g.set("body.mass", 3.0).unwrap();
    g.set("potential.alpha_hat", 0.1).unwrap();
    g.set("initial.phi_dot", 0.25).unwrap();
    g.set("initial.alpha", 0.5).unwrap();
    g.set("method.h", 0.01).unwrap();
    g.set("time.t_end", 2.0).unwrap();
    assert_eq!(g.manifold.radius, Some(2.0));
    assert_eq!(g.body.mass, 3.0);
    assert_eq!(g.potential.alpha_hat, Some(0.1));
    assert_eq!(g.initial.coordinate("phi_dot"), Some(0.25));
    assert_eq!(g.initial.alpha, Some(0.5));
    assert_eq!(g.method.h, Some(0.01));
    assert_eq!(g.time.t_end, 2.0);
    // Components need the field in the base scene.
    let e = g.set("initial.position.0", 1.0).unwrap_err().to_string();
    assert!(e.contains("initial.position.0") && e.contains("base scene"), "{e}");
    g.initial.position = Some(vec![0.0, 0.0, 1.0]);
    g.set("initial.position[2]", -1.0).unwrap();
    assert_eq!(g.initial.position.as_deref(), Some(&[0.0, 0.0, -1.0][..]));
    let e = g.set("initial.position.3", 1.0).unwrap_err().to_string();
    assert!(e.contains("out of range") && e.contains('3'), "{e}");
    let e = g.set("potential.terms.0.kappa", 1.0).unwrap_err().to_string();
    assert!(e.contains("potential.terms.0.kappa") && e.contains("0 terms"), "{e}");
    let e = g.set("initial.r", f64::NAN).unwrap_err().to_string();
    assert!(e.contains("initial.r") && e.contains("finite"), "{e}");
    // Matrix components.
    s.body.j = Some(vec![vec![0.2, 0.0, 0.0], vec![0.0, 0.3, 0.0], vec![0.0, 0.0, 0.4]]);
    s.set("body.J.1.1", 0.35).unwrap();
    assert_eq!(s.body.j.as_ref().unwrap()[1][1], 0.35);
}


/// Worker threads: at most one per member and, unless oversubscribing, one
/// per core.
#[test]
fn worker_threads_are_bounded_by_members_and_cores() {
    use framedyn::scenes::worker_threads;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert_eq!(worker_threads(5000, 1, false), 1);
    assert_eq!(worker_threads(5000, 1, true), 1);
    assert_eq!(worker_threads(1_000_000, 10_000, false), cores);
    assert_eq!(worker_threads(64, 10_000, true), 64);
    assert_eq!(worker_threads(1_000_000, 10_000, true), EnsembleOptions::MAX_THREADS);
    assert_eq!(worker_threads(1, 0, false), 1);
}

/// The scene `name`, shortened to about 60 steps and recorded at every
/// step or at 5 samples (so that changing `time.t_end` keeps it valid).
fn short(name: &str) -> Scene {
    let mut s = example(name).unwrap();
    let span = s.time.t_end - s.time.t0;
    s.time.t_end = s.time.t0 + span.min(60.0 * s.method.h.unwrap_or(span / 1000.0));
    if s.output.times.is_some() {
        s.output.times = None;
        s.output.samples = Some(5);
    }
    s
}

/// Each worker builds its first member in full and rebuilds only the model
/// and initial state (and the plan, when the table sets `time.*` or
/// `method.*`) of the next ones. On every embedded scene — every manifold,
/// body, potential family and method family, and a coordinate method on
/// its chart — with one thread (one worker sees every member in turn), the
/// members equal their single runs bit for bit, and an invalid member in
/// the middle is reported as the full build reports it without changing the
/// members after it.
#[test]
fn rebuilt_members_equal_single_runs_on_every_embedded_scene() {
    let mut scenes: Vec<(String, Scene)> = framedyn::scenes::EXAMPLES.iter().map(|(n, _)| (n.to_string(), short(n))).collect();
    let mut chart = short("s2-gyroscope-cosine");
    chart.method.name = "coordinate_rk4".into();
    scenes.push(("s2-gyroscope-cosine, coordinate_rk4".into(), chart));
    let mut checked = 0;
    for (name, base) in &scenes {
        let (m, t0, t_end) = (base.body.mass, base.time.t0, base.time.t_end);
        let mass = vec![m, 1.25 * m, -1.0, 0.8 * m];
        let t_ends = vec![t_end, t0 + 0.5 * (t_end - t0), t_end, t0 + 0.75 * (t_end - t0)];
        for table in [Table::new([("body.mass", mass.clone())]).unwrap(), Table::new([("body.mass", mass.clone()), ("time.t_end", t_ends.clone())]).unwrap()] {
            let out = ensemble(base, &table, Keep::All, Some(1));
            let fin = ensemble(base, &table, Keep::Final, Some(1));
            for i in 0..table.len() {
                let mut s = base.clone();
                for c in table.names() {
                    s.set(c, table.column(c).unwrap()[i]).unwrap();
                }
                let member = &out.members[i];
                match s.build() {
                    Err(e) => {
                        assert_eq!(member.status, MemberStatus::Invalid, "{name}, member {i}");
                        let msg = member.error.as_deref().unwrap();
                        assert!(msg.starts_with(&e.to_string()) && msg.contains(&format!("member {i}")), "{name}, member {i}: {msg} vs {e}");
                    }
                    Ok(mut sim) => {
                        let mut one = FlatSink::default();
                        let alone = sim.run(&mut one, &AtomicBool::new(false), &mut |_| {});
                        assert_eq!(member.status == MemberStatus::Failed, alone.is_err(), "{name}, member {i}");
                        assert_eq!(bits(out.records(i)), bits(&one.data), "{name}, member {i}");
                        assert_eq!(&out.columns, &one.columns, "{name}");
                        // Keep::Final: the last record, built once at the end, and
                        // the summary of every record.
                        let n = one.columns.len();
                        assert_eq!(bits(fin.records(i)), bits(&one.data[one.data.len().saturating_sub(n)..]), "{name}, member {i}, keep final");
                        let b = alone.as_ref().map_or_else(|f| &f.summary, |s| s);
                        for a in [member.summary.as_ref().unwrap(), fin.members[i].summary.as_ref().unwrap()] {
                            let key = |s: &framedyn::scenes::RunSummary| (s.steps, s.rejected, s.records, s.energy_initial.to_bits(), s.energy_drift.to_bits(), s.momentum_map_drift.to_bits(), s.max_defect.to_bits(), s.warnings.clone());
                            assert_eq!(key(a), key(b), "{name}, member {i}");
                        }
                        checked += 1;
                    }
                }
            }
            assert_eq!(out.members[2].status, MemberStatus::Invalid, "{name}: body.mass = -1 was accepted");
        }
    }
    assert!(checked >= 6 * scenes.len(), "only {checked} members ran");
}

/// `run_ensemble_blocks` hands over consecutive blocks in order; put back
/// together they are `run_ensemble`'s result (records, offsets, statuses,
/// summaries, messages naming the table's member index), and `Break` stops
/// before the next block.
#[test]
fn blocks_put_together_are_the_whole_ensemble() {
    use framedyn::scenes::run_ensemble_blocks;
    use std::ops::ControlFlow;
    let inertia = vec![0.2, 0.25, 0.3, -1.0, 0.35, 0.4, 0.45];
    let r: Vec<f64> = (0..7).map(|i| 0.4 + 0.1 * i as f64).collect();
    let table = Table::new([("body.inertia", inertia), ("initial.r", r)]).unwrap();
    let opts = EnsembleOptions { keep: Keep::All, threads: Some(2), oversubscribe: false };
    let whole = run_ensemble(&base(), &table, &opts, None, &AtomicBool::new(false), &|_| {}).unwrap();
    let mut firsts = Vec::new();
    let (mut data, mut offsets, mut members) = (Vec::new(), vec![0usize], Vec::new());
    run_ensemble_blocks(&base(), &table, &opts, None, &AtomicBool::new(false), &|_| {}, 3, &mut |first, b| {
        firsts.push(first);
        data.extend_from_slice(&b.data);
        let o = *offsets.last().unwrap();
        offsets.extend(b.offsets[1..].iter().map(|k| o + k));
        members.extend(b.members);
        ControlFlow::Continue(())
    })
    .unwrap();
    assert_eq!(firsts, [0, 3, 6]);
    assert_eq!((bits(&data), &offsets), (bits(&whole.data), &whole.offsets));
    // Everything but the wall-clock time of each run.
    let timeless = |ms: &[framedyn::scenes::MemberOutcome]| -> Vec<framedyn::scenes::MemberOutcome> {
        ms.iter().cloned().map(|mut m| {
            if let Some(s) = m.summary.as_mut() {
                s.wall_time = Default::default();
            }
            m
        }).collect()
    };
    assert_eq!(timeless(&members), timeless(&whole.members));
    let e = members[3].error.as_deref().unwrap();
    assert!(e.contains("member 3") && e.contains("body.inertia"), "{e}");
    let mut seen = 0;
    run_ensemble_blocks(&base(), &table, &opts, None, &AtomicBool::new(false), &|_| {}, 2, &mut |_, b| {
        seen += b.len();
        ControlFlow::Break(())
    })
    .unwrap();
    assert_eq!(seen, 2);
}
