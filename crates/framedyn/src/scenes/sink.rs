//! Where a run's records go: the columns, the [`RecordSink`] trait and the
//! two in-memory sinks ([`MemorySink`], one vector per record; [`FlatSink`],
//! one row-major buffer that numpy takes without a copy). The command-line
//! tool writes CSV and npz files through its own sinks.

use std::io;

use super::spec::Quantity;

/// One output column: its name, unit and group (see the [module docs](super)).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Column {
    /// Name, e.g. `"x0"` or `"energy"`.
    pub name: String,
    /// Unit in terms of `L`, `T`, `M` (`"1"`: dimensionless).
    pub unit: &'static str,
    /// The quantity group it belongs to (`None` for the time `t`).
    pub group: Option<Quantity>,
}

/// Where a run streams its records.
pub trait RecordSink {
    /// Called once before the first record with the column descriptions.
    fn columns(&mut self, columns: &[Column]) -> io::Result<()>;
    /// One record: one value per column.
    fn record(&mut self, row: &[f64]) -> io::Result<()>;
    /// A located event (default: ignored).
    fn event(&mut self, hit: &EventHit) -> io::Result<()> {
        let _ = hit;
        Ok(())
    }
    /// Whether the sink keeps only the last record (default: false). A run
    /// then still notes every record's energy, defect and momentum maps in
    /// its summary, but builds and passes only the last record (the same
    /// values), once the run has stopped.
    fn last_only(&self) -> bool {
        false
    }
}

/// A located event.
#[derive(Debug, Clone, PartialEq)]
pub struct EventHit {
    /// Index of the event (scene events first, then [`Simulation::add_event`](super::Simulation::add_event) ones).
    pub index: usize,
    /// Its name.
    pub name: String,
    /// The located time.
    pub t: f64,
    /// The record at `t` (the run's columns, [`Simulation::columns`](super::Simulation::columns)).
    pub row: Vec<f64>,
    /// True if `g` was rising through zero.
    pub rising: bool,
    /// True if the event stopped the run.
    pub terminal: bool,
}

/// A sink that keeps everything in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MemorySink {
    /// The columns.
    pub columns: Vec<Column>,
    /// The records.
    pub rows: Vec<Vec<f64>>,
    /// The located events.
    pub events: Vec<EventHit>,
}

impl MemorySink {
    /// The values of the column `name`, if present.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self.columns.iter().position(|c| c.name == name)?;
        Some(self.rows.iter().map(|r| r[j]).collect())
    }
}

impl RecordSink for MemorySink {
    fn columns(&mut self, columns: &[Column]) -> io::Result<()> {
        self.columns = columns.to_vec();
        Ok(())
    }
    fn record(&mut self, row: &[f64]) -> io::Result<()> {
        self.rows.push(row.to_vec());
        Ok(())
    }
    fn event(&mut self, hit: &EventHit) -> io::Result<()> {
        self.events.push(hit.clone());
        Ok(())
    }
}

/// A sink that keeps every record in one row-major buffer (`rows × columns`
/// values): one growing allocation instead of [`MemorySink`]'s one per
/// record, and the layout numpy takes without a copy (the Python module
/// returns it as `Solution.data`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FlatSink {
    /// The columns.
    pub columns: Vec<Column>,
    /// The records, row-major: record `i` is `data[i·ncols .. (i+1)·ncols]`.
    pub data: Vec<f64>,
    /// The number of records.
    pub rows: usize,
    /// The located events.
    pub events: Vec<EventHit>,
}

impl FlatSink {
    /// Record `i`.
    pub fn row(&self, i: usize) -> &[f64] {
        let n = self.columns.len();
        &self.data[i * n..(i + 1) * n]
    }

    /// The values of the column `name`, if present.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self.columns.iter().position(|c| c.name == name)?;
        Some(self.data.iter().skip(j).step_by(self.columns.len()).copied().collect())
    }
}

impl RecordSink for FlatSink {
    fn columns(&mut self, columns: &[Column]) -> io::Result<()> {
        self.columns = columns.to_vec();
        Ok(())
    }
    fn record(&mut self, row: &[f64]) -> io::Result<()> {
        if self.data.capacity() - self.data.len() < row.len() {
            // Grow by doubling, and fail with an error instead of aborting
            // the process when memory is exhausted.
            let extra = row.len().max(self.data.len());
            if self.data.try_reserve(extra).is_err() && self.data.try_reserve_exact(row.len()).is_err() {
                return Err(io::Error::new(
                    io::ErrorKind::OutOfMemory,
                    format!("out of memory keeping record {} ({} values kept): record fewer (output.every, output.samples)", self.rows + 1, self.data.len()),
                ));
            }
        }
        self.data.extend_from_slice(row);
        self.rows += 1;
        Ok(())
    }
    fn event(&mut self, hit: &EventHit) -> io::Result<()> {
        self.events.push(hit.clone());
        Ok(())
    }
}

