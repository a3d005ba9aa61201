//! Check reports, kept in memory for a stated time at unguessable addresses (128 random bits), then
//! forgotten: nothing a student uploaded outlives its report. The store is bounded in count and in bytes;
//! past either, the oldest reports go first.

use std::collections::{HashMap, VecDeque};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// One report: its JSON and its pictures (PNG bytes), by name.
pub struct Report {
    pub json: String,
    pub pictures: Vec<(&'static str, Vec<u8>)>,
    created: Instant,
}

impl Report {
    pub fn new(json: String, pictures: Vec<(&'static str, Vec<u8>)>) -> Self {
        Self { json, pictures, created: Instant::now() }
    }

    fn bytes(&self) -> usize {
        self.json.len() + self.pictures.iter().map(|(_, p)| p.len()).sum::<usize>()
    }
}

/// A new report's id: 128 bits of the system's random source, in 32 hexadecimal digits.
pub fn new_id() -> std::io::Result<String> {
    let mut bits = [0u8; 16];
    getrandom::fill(&mut bits).map_err(|e| std::io::Error::other(e.to_string()))?;
    Ok(bits.iter().map(|b| format!("{b:02x}")).collect())
}

/// The reports kept now.
pub struct Reports {
    kept: Mutex<Kept>,
    /// How long a report is kept.
    pub lifetime: Duration,
    max_count: usize,
    max_bytes: usize,
}

#[derive(Default)]
struct Kept {
    reports: HashMap<String, std::sync::Arc<Report>>,
    /// Ids oldest first.
    order: VecDeque<String>,
    bytes: usize,
}

impl Kept {
    fn remove_oldest(&mut self) {
        if let Some(id) = self.order.pop_front() {
            if let Some(report) = self.reports.remove(&id) {
                self.bytes -= report.bytes();
            }
        }
    }
}

impl Reports {
    pub fn new(lifetime: Duration, max_count: usize, max_bytes: usize) -> Self {
        Self { kept: Mutex::new(Kept::default()), lifetime, max_count, max_bytes }
    }

    /// Keeps `report` under `id` (from [`new_id`]).
    pub fn keep(&self, id: String, report: Report) {
        let mut kept = self.lock();
        kept.bytes += report.bytes();
        kept.reports.insert(id.clone(), std::sync::Arc::new(report));
        kept.order.push_back(id.clone());
        while kept.reports.len() > self.max_count || kept.bytes > self.max_bytes {
            kept.remove_oldest();
        }
    }

    /// The report `id`, unless it was never made or is forgotten.
    pub fn get(&self, id: &str) -> Option<std::sync::Arc<Report>> {
        self.forget_expired();
        self.lock().reports.get(id).cloned()
    }

    /// Forgets the reports older than their lifetime.
    pub fn forget_expired(&self) {
        let mut kept = self.lock();
        while let Some(oldest) = kept.order.front() {
            let expired = kept.reports.get(oldest).is_none_or(|r| r.created.elapsed() >= self.lifetime);
            if !expired {
                break;
            }
            kept.remove_oldest();
        }
    }

    /// How many reports are kept now.
    pub fn count(&self) -> usize {
        self.lock().reports.len()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Kept> {
        self.kept.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(bytes: usize) -> Report {
        Report::new(String::new(), vec![("yours", vec![0; bytes])])
    }

    #[test]
    fn reports_are_forgotten_past_their_lifetime_and_bounds() {
        let reports = Reports::new(Duration::from_millis(50), 3, 1000);
        let keep = |reports: &Reports, bytes| {
            let id = new_id().unwrap();
            reports.keep(id.clone(), report(bytes));
            id
        };
        let first = keep(&reports, 10);
        assert_eq!(first.len(), 32);
        assert!(reports.get(&first).is_some());
        std::thread::sleep(Duration::from_millis(60));
        assert!(reports.get(&first).is_none(), "kept past its lifetime");
        let reports = Reports::new(Duration::from_secs(60), 3, 1000);
        let ids: Vec<String> = (0..4).map(|_| keep(&reports, 10)).collect();
        assert_ne!(ids[0], ids[1]);
        assert!(reports.get(&ids[0]).is_none() && reports.get(&ids[3]).is_some(), "count bound");
        assert_eq!(reports.count(), 3);
        keep(&reports, 990);
        assert_eq!(reports.count(), 2, "byte bound: only the newest two fit in 1000 bytes");
    }
}
