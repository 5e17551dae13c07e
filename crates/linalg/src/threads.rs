//! Work the root's loops share between the cores faer may use (its global
//! parallelism): the products with W and the filling of dense blocks, which
//! are bound by the reading of W and run on one core otherwise while faer's
//! factorisations use all of them.

/// Below this many multiply-adds a loop stays on one thread (starting a
/// thread costs tens of microseconds).
const MIN_WORK: f64 = 1e6;

/// Runs `f(first, chunk)` on consecutive chunks of `data` made of whole
/// groups of `group` entries (`first`: the index of the chunk's first
/// group), one chunk per thread when `work` multiply-adds are worth it,
/// else `f(0, data)`.
pub fn for_each_chunk<F>(data: &mut [f64], group: usize, work: f64, f: F)
where
    F: Fn(usize, &mut [f64]) + Sync,
{
    // Nothing to fill (an empty block: `f` would cut it into chunks of 0).
    if data.is_empty() {
        return;
    }
    let groups = data.len() / group.max(1);
    let threads = faer::get_global_parallelism().degree().min(groups);
    if threads < 2 || work < MIN_WORK {
        return f(0, data);
    }
    let per = groups.div_ceil(threads);
    std::thread::scope(|s| {
        let mut chunks = data.chunks_mut(per * group).enumerate();
        let (_, mine) = chunks.next().expect("at least two groups");
        for (k, chunk) in chunks {
            let f = &f;
            s.spawn(move || f(k * per, chunk));
        }
        f(0, mine);
    });
}

/// `f` of each item, on up to `workers` threads taking the items in turn
/// (the calling thread one of them); the results in the order of `items`.
pub fn map_side_by_side<T, R, F>(items: Vec<T>, workers: usize, f: F) -> Vec<R>
where
    T: Send,
    R: Send,
    F: Fn(T) -> R + Sync,
{
    if workers < 2 || items.len() < 2 {
        return items.into_iter().map(f).collect();
    }
    use std::sync::Mutex;
    let n = items.len();
    let queue: Mutex<std::iter::Enumerate<std::vec::IntoIter<T>>> =
        Mutex::new(items.into_iter().enumerate());
    let results: Mutex<Vec<Option<R>>> = Mutex::new((0..n).map(|_| None).collect());
    let work = || loop {
        let next = queue.lock().unwrap_or_else(|e| e.into_inner()).next();
        let Some((i, item)) = next else { break };
        let r = f(item);
        results.lock().unwrap_or_else(|e| e.into_inner())[i] = Some(r);
    };
    std::thread::scope(|s| {
        for _ in 1..workers.min(n) {
            s.spawn(work);
        }
        work();
    });
    results
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_iter()
        .flatten()
        .collect()
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
