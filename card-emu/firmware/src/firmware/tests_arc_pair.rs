//! Layout 1.13: the two entries of a normal-vector arc move (`MC_OP_GROUP_MOVE_CIRCULAR_NORMAL`
//! and `MC_OP_GROUP_CIRCULAR_PLANE`) as the command manager pairs them: taken together, each
//! answered; a piece alone or out of order refused with `MC_NACK_ARC_PIECE` and nothing queued;
//! an entry after a lone first piece served on its own; the pieces never timed.

use super::tests_timed::Card;
use super::*;
use firmware_proto::{GroupState, Opcode};

const R: f64 = 5_000.0;

/// A card of three axes with group 0 over them, powered and enabled.
fn card() -> Card {
    Card::with_group(3)
}

/// The two entries of a half turn in the XY plane (normal +Z) around (−R, 0, 0) from the
/// origin, for group `g`; `normal` is the plane's normal.
fn pair(c: &mut Card, g: u16, normal: [f64; 3]) -> [Command; 2] {
    let m = c.entry(
        Opcode::GroupMoveCircularNormal,
        g,
        0,
        &[2e4, 4e5, 4e5, 4e7, -R, 0.0, 0.0, -2.0 * R, 0.0, 0.0, 0.0],
    );
    let mut args = vec![0.0, 1.0, 2.0];
    args.extend_from_slice(&normal);
    let p = c.entry(Opcode::GroupCircularPlane, g, 0, &args);
    [m, p]
}

fn queued(c: &Card) -> u32 {
    let g = c.fw.group(0).unwrap();
    g.status(0).queued + u32::from(g.status(0).active_seq != 0)
}

/// The pair published together: both acked on the tick they came, one move queued; it runs
/// under the first entry's seq, half a turn long.
#[test]
fn a_pair_published_together_is_one_move_and_each_entry_is_answered() {
    let mut c = card();
    let p = pair(&mut c, 0, [0.0, 0.0, 1.0]);
    c.send(&p);
    assert_eq!(c.answer(p[0].seq), Some(Ok(0)));
    assert_eq!(c.answer(p[1].seq), Some(Ok(0)));
    assert_eq!((c.answers(p[0].seq), c.answers(p[1].seq)), (1, 1));
    assert_eq!(queued(&c), 1);
    // (the harness's encoders stand still: the move is watched starting, not finished)
    for _ in 0..10 {
        c.tick();
    }
    let st = c.fw.group(0).unwrap().status(c.fw.tick_count());
    assert_eq!(
        st.active_seq, p[0].seq,
        "the move runs under the first entry's seq"
    );
    let half = core::f64::consts::PI * R;
    assert!(
        (st.path_len - half).abs() <= 1e-9 * half,
        "length {}",
        st.path_len
    );
    assert!(st.path_pos > 0.0 && st.path_pos < st.path_len);
}

/// A refused pair: both entries get the move's refusal (here a zero normal), nothing queued.
#[test]
fn a_refused_pair_answers_both_entries_with_the_refusal() {
    let mut c = card();
    let p = pair(&mut c, 0, [0.0; 3]);
    c.send(&p);
    assert_eq!(c.answer(p[0].seq), Some(Err(NackCode::ArcNormal)));
    assert_eq!(c.answer(p[1].seq), Some(Err(NackCode::ArcNormal)));
    assert_eq!(queued(&c), 0);
}

/// Every piece alone or out of order is `MC_NACK_ARC_PIECE`, answered once, and queues
/// nothing: the second alone; the second before the first (each is then alone); the first
/// followed by another command (refused; the other served on its own: a NOP acked); the
/// first followed by the second of another group (both alone); the first last in the ring.
/// Timed, the first is `MC_NACK_TIMED_ALONE` (with its timing) and the second then alone.
#[test]
fn a_piece_alone_or_out_of_order_is_refused_and_queues_nothing() {
    let mut c = card();
    let piece = NackCode::ArcPiece;
    let [m, p] = pair(&mut c, 0, [0.0, 0.0, 1.0]);
    c.send(&[p]);
    assert_eq!(c.answer(p.seq), Some(Err(piece)), "the second alone");
    let [m2, p2] = pair(&mut c, 0, [0.0, 0.0, 1.0]);
    c.send(&[p2, m2]);
    assert_eq!(c.answer(p2.seq), Some(Err(piece)), "second first");
    assert_eq!(c.answer(m2.seq), Some(Err(piece)), "then the first");
    let nop = c.entry(Opcode::Nop, 0, 0, &[]);
    c.send(&[m, nop]);
    assert_eq!(c.answer(m.seq), Some(Err(piece)), "the first, then a NOP");
    assert_eq!(c.answer(nop.seq), Some(Ok(0)), "the NOP served on its own");
    let [m3, _] = pair(&mut c, 0, [0.0, 0.0, 1.0]);
    let [_, p3] = pair(&mut c, 1, [0.0, 0.0, 1.0]);
    c.send(&[m3, p3]);
    assert_eq!(c.answer(m3.seq), Some(Err(piece)), "another group's second");
    assert_eq!(c.answer(p3.seq), Some(Err(piece)));
    let [m4, _] = pair(&mut c, 0, [0.0, 0.0, 1.0]);
    c.send(&[m4]);
    assert_eq!(c.answer(m4.seq), Some(Err(piece)), "the first alone");
    let tick = c.fw.tick_count() + 10;
    let at = c.entry(Opcode::AtTick, 0, 0, &[tick as f64, 0.0]);
    let [m5, p5] = pair(&mut c, 0, [0.0, 0.0, 1.0]);
    c.send(&[at, m5, p5]);
    assert_eq!(c.answer(at.seq), Some(Err(NackCode::TimedAlone)));
    assert_eq!(c.answer(m5.seq), Some(Err(NackCode::TimedAlone)));
    assert_eq!(c.answer(p5.seq), Some(Err(piece)));
    for s in [
        m.seq, p.seq, m2.seq, p2.seq, m3.seq, p3.seq, m4.seq, m5.seq, p5.seq,
    ] {
        assert_eq!(c.answers(s), 1, "seq {s} answered once");
    }
    assert_eq!(queued(&c), 0);
    assert_eq!(c.fw.group(0).unwrap().state, GroupState::Standby);
    // And the pair still goes through afterwards.
    let ok = pair(&mut c, 0, [0.0, 0.0, 1.0]);
    c.send(&ok);
    assert_eq!(c.answer(ok[0].seq), Some(Ok(c.fw.tick_count())));
    assert_eq!(queued(&c), 1);
}
