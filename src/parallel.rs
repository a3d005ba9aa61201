//! Work made on all the cores, item by item: the CPU reference's rows of rays, the environment's maps, and
//! the pipelines lavapipe builds.

use std::sync::atomic::{AtomicU32, Ordering};

/// `row(y)` for every y from 0 to `count`, one after the other, the rows shared among the cores as they
/// come free (rows may cost very different amounts). A panic in one row is the caller's panic.
pub fn rows<T: Send>(count: u32, row: impl Fn(u32) -> Vec<T> + Sync) -> Vec<T> {
    let threads = std::thread::available_parallelism().map_or(1, usize::from).min(count.max(1) as usize);
    let next = AtomicU32::new(0);
    let mut made: Vec<(u32, Vec<T>)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut rows = Vec::new();
                    loop {
                        let y = next.fetch_add(1, Ordering::Relaxed);
                        if y >= count {
                            return rows;
                        }
                        rows.push((y, row(y)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|worker| worker.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)))
            .collect()
    });
    made.sort_by_key(|(y, _)| *y);
    made.into_iter().flat_map(|(_, row)| row).collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn rows_come_back_in_order_whoever_made_them() {
        let made = super::rows(37, |y| vec![y; y as usize % 3]);
        let expected: Vec<u32> = (0..37).flat_map(|y| vec![y; y as usize % 3]).collect();
        assert_eq!(made, expected);
        assert!(super::rows(0, |y| vec![y]).is_empty());
    }
}
