//! Cell crossings under Lees–Edwards boundaries (see `emdstar_system::LeesEdwards`).
//! The rows of cells across the sheared y face slide along x with the images, so a
//! cell in a border row takes the whole opposite border row (within one cell in z)
//! as its neighbours there, as DynamO's sheared cells do: a particle that enters a
//! border row tests every particle of the opposite one, and the pair predictions
//! across the face follow the sliding image (x shifted by the offset Δ(t), x-velocity
//! by γ̇ L_y) through every periodic image along x that can meet it.

use super::BroadPhase;
use super::crossings::Crossings;
use crate::cells::NONE;
use crate::queue::EventQueue;
use crate::state::State;
use emdstar_system::LeesEdwards;

impl Crossings {
    /// The earliest collision of `i` (advanced to now) before `best` with the particles
    /// of the border rows across the sheared face at the y offsets `dys` and z offsets
    /// `dzs` (each −1, 0 or 1) from its cell `c`: (time, partner or NONE, now), and
    /// whether a particle met blocks the rotation of a running exception-(a) probe.
    pub(super) fn earliest_across<Q: EventQueue>(
        &self,
        s: &State<Q>,
        le: &LeesEdwards,
        i: usize,
        c: [u32; 3],
        (dys, dzs): (&[i64], &[i64]),
        mut best: f64,
    ) -> ((f64, u32, bool), bool) {
        let now = s.time;
        let (delta, speed) = (le.offset(now), le.image_speed());
        let [lx, ly, lz] = le.size;
        let (pi, vi) = (s.slot[i].kin.pos, s.slot[i].kin.vel);
        let ri = s.slot[i].kin.radius;
        let dims = self.grid.shape.dims;
        let (mut best_j, mut best_now) = (NONE, false);
        let probe = s.probe_slot(i);
        let mut blocked = false;
        for &dy in dys {
            let (y, up) = self.grid.around[1][c[1] as usize][(dy + 1) as usize];
            if y == NONE || up == 0 {
                continue;
            }
            // The row's particles appear `up` boxes above: x + up·Δ, v_x + up·γ̇L_y.
            let up = f64::from(up);
            for &dz in dzs {
                let (z, sz) = self.grid.around[2][c[2] as usize][(dz + 1) as usize];
                if z == NONE {
                    continue;
                }
                let row = dims[0] * (y as usize + dims[1] * z as usize);
                for cell in row..row + dims[0] {
                    let mut j = self.grid.first(cell as u32);
                    while j != NONE {
                        let ju = j as usize;
                        if ju != i && !s.in_shared_transient(i, ju) {
                            let (pj, vj) = s.state_at(ju, now);
                            let r = [
                                pi[0] - pj[0] - up * delta,
                                pi[1] - pj[1] - up * ly,
                                pi[2] - pj[2] - f64::from(sz) * lz,
                            ];
                            let v = [vi[0] - vj[0] - up * speed, vi[1] - vj[1], vi[2] - vj[2]];
                            let sigma = ri + s.slot[ju].kin.radius;
                            if let Some((probe, slot)) = &probe {
                                // The nearest image along x of the row's image.
                                let r = [r[0] - lx * (r[0] / lx).round(), r[1], r[2]];
                                blocked |= s.blocks_rotation(probe, *slot, ju, r, pj, sigma);
                            }
                            let dt = crate::detect::sphere_x_images(r, v, sigma, lx);
                            if now + dt < best {
                                best = now + dt;
                                best_j = j;
                                best_now = dt == 0.0;
                            }
                        }
                        j = self.grid.next(j);
                    }
                }
            }
        }
        ((best, best_j, best_now), blocked)
    }

    /// [`BroadPhase::predict_pairs`] in a sheared box: the cells that do not wrap in y
    /// as usual, the border row across the face whole.
    pub(super) fn predict_pairs_sheared<Q: EventQueue>(
        &self,
        s: &mut State<Q>,
        le: &LeesEdwards,
        i: usize,
    ) {
        let c = self.grid.coords[i];
        let set = self.grid.neighbourhood(c);
        let same_rows = set.iter().filter(|(_, shift)| shift[1] == 0.0);
        let (found, blocked_here) = self.earliest_in(s, i, same_rows, s.slot[i].ev.coll_time);
        s.keep_earliest(i, found);
        let all = [-1, 0, 1];
        let (found, blocked_across) =
            self.earliest_across(s, le, i, c, (&all, &all), s.slot[i].ev.coll_time);
        s.keep_earliest(i, found);
        if blocked_here || blocked_across {
            s.block_probe();
        }
    }

    /// The new layer of `i` after entering cell `c` along `axis` in direction `dir`
    /// (not through the sheared face) in a sheared box: the cells of the layer that do
    /// not wrap in y; across the face, nothing new along x (the whole row is tested
    /// already), the next z layer of the row along z, the whole row on entering a
    /// border row along y.
    pub(super) fn scan_new_layer_sheared<Q: EventQueue>(
        &self,
        s: &mut State<Q>,
        le: &LeesEdwards,
        i: usize,
        (c, axis, dir): ([u32; 3], usize, i64),
    ) {
        let layer = self.grid.new_layer(c, axis, dir);
        let same_rows = layer.iter().filter(|(_, shift)| shift[1] == 0.0);
        let (found, _) = self.earliest_in(s, i, same_rows, s.slot[i].ev.coll_time);
        s.keep_earliest(i, found);
        let all = [-1, 0, 1];
        let across: Option<(&[i64], &[i64])> = match axis {
            1 => Some((&[dir], &all)),
            2 => Some((&all, &[dir])),
            _ => None,
        };
        if let Some(offsets) = across {
            let (found, _) = self.earliest_across(s, le, i, c, offsets, s.slot[i].ev.coll_time);
            s.keep_earliest(i, found);
        }
    }

    /// `i` (advanced to now) leaves through the sheared y face in direction `dir`: it
    /// re-enters at the opposite face as its image, x shifted by ∓Δ(t) and v_x by
    /// ∓γ̇ L_y (Lees & Edwards 1972), is filed in its new cell (another column) and
    /// predicted anew (a pending E^v velocity is shifted with it). Its partners'
    /// predictions stand: the trajectory is the same.
    pub(super) fn cross_sheared_face<Q: EventQueue>(
        &mut self,
        s: &mut State<Q>,
        le: &LeesEdwards,
        i: usize,
        (next, shift, dir): (u32, f64, i64),
    ) {
        let up = dir as f64;
        let kin = &mut s.slot[i].kin;
        kin.pos[1] += shift;
        kin.pos[0] -= up * le.offset(s.time);
        kin.vel[0] -= up * le.image_speed();
        // A pending eMD* E^v velocity is the image's too (the relative motion of the
        // pair, one of which may now be across the face, is unchanged).
        if s.slot[i].ev.pending_time.is_finite() {
            s.pending_vel[i][0] -= up * le.image_speed();
        }
        s.image[i][1] += dir as i32;
        // x back into the box (y stays on the face it entered through, as the cell
        // coordinate says, whatever the round-off).
        let mut p = s.slot[i].kin.pos;
        let (lo, lx) = (le.lo[0], le.size[0]);
        if p[0] < lo {
            p[0] += lx;
            s.image[i][0] -= 1;
        } else if p[0] >= lo + lx {
            p[0] -= lx;
            s.image[i][0] += 1;
        }
        s.slot[i].kin.pos = p;
        let mut c = self.grid.coords_of(p);
        c[1] = next;
        self.grid.relocate(i, c);
        self.predict(s, i);
    }
}
