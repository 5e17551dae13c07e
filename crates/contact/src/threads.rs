//! Work the root's loops share between the cores faer may use (its global
//! parallelism): the products with W and the filling of dense blocks, which
//! are bound by the reading of W and run on one core otherwise while faer's
//! factorisations use all of them.

use faer::Par;

/// Below this many multiply-adds a loop stays on one thread (starting a
/// thread costs tens of microseconds).
const MIN_WORK: f64 = 1e6;

/// The number of threads faer's global parallelism allows.
fn degree() -> usize {
    match faer::get_global_parallelism() {
        Par::Seq => 1,
        Par::Rayon(n) => n.get(),
    }
}

/// Runs `f(first, chunk)` on consecutive chunks of `data` made of whole
/// groups of `group` entries (`first`: the index of the chunk's first
/// group), one chunk per thread when `work` multiply-adds are worth it,
/// else `f(0, data)`.
pub(crate) fn for_each_chunk<F>(data: &mut [f64], group: usize, work: f64, f: F)
where
    F: Fn(usize, &mut [f64]) + Sync,
{
    let groups = data.len() / group.max(1);
    let threads = degree().min(groups);
    if threads < 2 || work < MIN_WORK {
        return f(0, data);
    }
    let per = groups.div_ceil(threads);
    let parts: Vec<(usize, &mut [f64])> = data
        .chunks_mut(per * group)
        .enumerate()
        .map(|(k, chunk)| (k * per, chunk))
        .collect();
    for_each_part(parts, |(first, chunk)| f(first, chunk));
}

/// Runs `f` on each part, each on its own thread (the first on this one).
fn for_each_part<T: Send>(parts: Vec<T>, f: impl Fn(T) + Sync) {
    let mut parts = parts.into_iter();
    let Some(mine) = parts.next() else { return };
    std::thread::scope(|s| {
        for part in parts {
            let f = &f;
            s.spawn(move || f(part));
        }
        f(mine);
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chunks_cover_the_data_once_in_whole_groups() {
        for (len, group, work) in [(10, 1, 1e9), (12, 3, 1e9), (7, 1, 0.0), (1, 1, 1e9)] {
            let mut data = vec![0.0; len];
            for_each_chunk(&mut data, group, work, |first, chunk| {
                assert_eq!(chunk.len() % group, 0);
                for (i, v) in chunk.iter_mut().enumerate() {
                    *v += (first * group + i) as f64;
                }
            });
            let want: Vec<f64> = (0..len).map(|i| i as f64).collect();
            assert_eq!(data, want);
        }
    }
}
