//! Reading one column chunk with the `parquet` crate's column reader: values with their nulls
//! located, `segment` strings mapped to label indices, and the segment labels of a row group.
//! Every error names the file, the row group and the column.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use parquet::basic::Encoding;
use parquet::column::page::{Page, PageReader};
use parquet::column::reader::{ColumnReaderImpl, get_column_reader};
use parquet::data_type::{ByteArray, ByteArrayType, DataType};
use parquet::errors::ParquetError;
use parquet::file::reader::ChunkReader;

use crate::error::{DataError, RowRef};
use crate::pq_batch::ReadPlan;
use crate::pq_dict::dictionary_values;
use crate::pq_pages::{at, pages, pq_err};
use crate::schema::MAX_BATCH_ROWS;
use crate::schema::{MAX_SEGMENT_LABELS, SEGMENT_COLUMN};

/// One column chunk being read, value by value in row order.
pub(crate) struct Column<T: DataType> {
    reader: ColumnReaderImpl<T>,
    max_def: i16,
    rg: usize,
    name: &'static str,
    /// Dataset row of the next value.
    next_row: u64,
    /// Definition levels of the last read (nullable columns).
    levels: Vec<i16>,
}

impl<T: DataType> Column<T> {
    /// Start reading column `name` (leaf `leaf`) of row group `rg`, whose first row is dataset
    /// row `first_row`, from `source`.
    pub fn open<R: ChunkReader + 'static>(
        plan: &ReadPlan,
        (rg, leaf, name): (usize, usize, &'static str),
        first_row: u64,
        source: Arc<R>,
    ) -> Result<Self, DataError> {
        let descr = plan.metadata.file_metadata().schema_descr().column(leaf);
        let max_def = descr.max_def_level();
        let pages = pages(plan, rg, leaf, name, source)?;
        let reader =
            T::get_column_reader(get_column_reader(descr, Box::new(pages))).ok_or_else(|| {
                DataError::corrupt(
                    &plan.path,
                    format!("{}: unexpected physical type", at(rg, name)),
                )
            })?;
        Ok(Self {
            reader,
            max_def,
            rg,
            name,
            next_row: first_row,
            levels: Vec::new(),
        })
    }

    fn err(&self, file: &Path, e: ParquetError) -> DataError {
        pq_err(file, &at(self.rg, self.name), e)
    }

    /// Read the next `n` values into `values` (replacing its contents); a null is reported at
    /// its row, a column that ends early as corrupt.
    pub fn read(&mut self, file: &Path, n: usize, values: &mut Vec<T::T>) -> Result<(), DataError> {
        values.clear();
        self.levels.clear();
        let mut rows = 0;
        while rows < n {
            let def = (self.max_def > 0).then_some(&mut self.levels);
            let (got, _, _) = self
                .reader
                .read_records(n - rows, def, None, values)
                .map_err(|e| self.err(file, e))?;
            if got == 0 {
                return Err(DataError::corrupt(
                    file,
                    format!(
                        "{}: the column ends at row {} but the row group goes on",
                        at(self.rg, self.name),
                        self.next_row + rows as u64
                    ),
                ));
            }
            rows += got;
        }
        if self.max_def > 0
            && let Some(i) = self.levels.iter().position(|&d| d < self.max_def)
        {
            return Err(DataError::BadValue {
                file: file.to_path_buf(),
                at: RowRef::row(self.next_row + i as u64),
                column: self.name.to_string(),
                text: String::new(),
                reason: "missing value (null)",
            });
        }
        if values.len() != n {
            return Err(self.err(
                file,
                ParquetError::General("values and rows disagree".into()),
            ));
        }
        self.next_row += n as u64;
        Ok(())
    }

    /// Check that the column chunk holds no value beyond the row group's rows.
    pub fn finish(&mut self, file: &Path, scratch: &mut Vec<T::T>) -> Result<(), DataError> {
        scratch.clear();
        self.levels.clear();
        let def = (self.max_def > 0).then_some(&mut self.levels);
        let (extra, _, _) = self
            .reader
            .read_records(1, def, None, scratch)
            .map_err(|e| self.err(file, e))?;
        if extra > 0 {
            return Err(DataError::corrupt(
                file,
                format!(
                    "{}: the column holds more values than the row group's {} rows",
                    at(self.rg, self.name),
                    self.next_row
                ),
            ));
        }
        Ok(())
    }
}

impl Column<ByteArrayType> {
    /// Read the next `n` segment values and map each to its label index in `out`.
    pub fn read_segment(
        &mut self,
        file: &Path,
        n: usize,
        lookup: &HashMap<String, u16>,
        values: &mut Vec<ByteArray>,
        out: &mut Vec<u16>,
    ) -> Result<(), DataError> {
        let first_row = self.next_row;
        self.read(file, n, values)?;
        out.clear();
        let mut prev: Option<(&ByteArray, u16)> = None;
        for (i, v) in values.iter().enumerate() {
            if let Some((p, idx)) = prev
                && p == v
            {
                out.push(idx);
                continue;
            }
            let bad = |reason: String| DataError::BadSegment {
                file: file.to_path_buf(),
                at: RowRef::row(first_row + i as u64),
                reason,
            };
            let s = v
                .as_utf8()
                .map_err(|e| bad(format!("value is not a UTF-8 string: {e}")))?;
            let idx = *lookup
                .get(s)
                .ok_or_else(|| bad(format!("value {s:?} is not in the column's dictionary")))?;
            prev = Some((v, idx));
            out.push(idx);
        }
        Ok(())
    }
}

/// Labels found so far (in order) and their indices.
#[derive(Default)]
pub(crate) struct Labels {
    pub list: Vec<String>,
    pub lookup: HashMap<String, u16>,
}

impl Labels {
    fn add(&mut self, file: &Path, first_row: u64, s: &str) -> Result<(), DataError> {
        if self.lookup.contains_key(s) {
            return Ok(());
        }
        if self.list.len() >= MAX_SEGMENT_LABELS {
            return Err(DataError::BadSegment {
                file: file.to_path_buf(),
                at: RowRef::row(first_row),
                reason: format!("more than {MAX_SEGMENT_LABELS} distinct labels"),
            });
        }
        self.lookup.insert(s.to_string(), self.list.len() as u16);
        self.list.push(s.to_string());
        Ok(())
    }

    /// Add the labels of row group `rg`'s segment chunk (new ones only): the dictionary page
    /// when every data page is dictionary-encoded (this keeps the writer's exact label list,
    /// unused labels included), otherwise the distinct values in order of appearance. Returns
    /// whether the chunk's label indices can be read from its pages directly
    /// ([`crate::pq_dict::SegmentIndices`]: a required column, dictionary-encoded).
    pub fn collect(
        &mut self,
        plan: &ReadPlan,
        rg: usize,
        leaf: usize,
        first_row: u64,
    ) -> Result<bool, DataError> {
        let file = plan.path.as_path();
        let where_ = at(rg, SEGMENT_COLUMN);
        let corrupt = |why: &str| DataError::corrupt(file, format!("{where_}: {why}"));
        let mut reader = pages(plan, rg, leaf, SEGMENT_COLUMN, Arc::clone(&plan.file))?;
        let mut dict = None;
        let mut all_dict_encoded = true;
        while let Some(page) = reader
            .get_next_page()
            .map_err(|e| pq_err(file, &where_, e))?
        {
            match page {
                Page::DictionaryPage {
                    buf, num_values, ..
                } if dict.is_none() => {
                    dict = Some((buf, num_values));
                }
                Page::DictionaryPage { .. } => return Err(corrupt("a second dictionary page")),
                Page::DataPage { encoding, .. } | Page::DataPageV2 { encoding, .. } => {
                    if !matches!(
                        encoding,
                        Encoding::RLE_DICTIONARY | Encoding::PLAIN_DICTIONARY
                    ) {
                        all_dict_encoded = false;
                        break;
                    }
                }
            }
        }
        match dict {
            Some((buf, num_values)) if all_dict_encoded => {
                for s in dictionary_values(&buf, num_values).map_err(|why| corrupt(&why))? {
                    self.add(file, first_row, s)?;
                }
                let descr = plan.metadata.file_metadata().schema_descr().column(leaf);
                Ok(descr.max_def_level() == 0 && descr.max_rep_level() == 0)
            }
            _ => {
                let mut column = Column::<ByteArrayType>::open(
                    plan,
                    (rg, leaf, SEGMENT_COLUMN),
                    first_row,
                    Arc::clone(&plan.file),
                )?;
                let mut left = plan.rg_rows.get(rg).copied().unwrap_or(0);
                let (mut values, mut row) = (Vec::new(), first_row);
                while left > 0 {
                    let n = left.min(MAX_BATCH_ROWS);
                    column.read(file, n, &mut values)?;
                    let mut prev: Option<&ByteArray> = None;
                    for v in &values {
                        if prev != Some(v) {
                            let s = v.as_utf8().map_err(|e| DataError::BadSegment {
                                file: file.to_path_buf(),
                                at: RowRef::row(row),
                                reason: format!("value is not a UTF-8 string: {e}"),
                            })?;
                            self.add(file, row, s)?;
                            prev = Some(v);
                        }
                        row += 1;
                    }
                    left -= n;
                }
                Ok(false)
            }
        }
    }
}
