//! The grid of a sweep: one or more scene keys, each with its values, and every combination of them in a
//! fixed order, with the label and file name of each combination's tile and the shares (`--shard K/N`) a
//! sweep is split into. Pure data: `vk-render sweep` and `vk-render sheet` build their tiles from it, and the
//! Python binding enumerates the same combinations and file names.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use crate::scene::shortened;
use crate::scene::Override;

/// One value of a grid parameter: `text` as the user wrote it (labels and file names use it), `value` the
/// TOML value it sets.
#[derive(Clone, Debug, PartialEq)]
pub struct GridValue {
    /// The value as the user wrote it, trimmed: what labels and file names show.
    pub text: String,
    /// The TOML value it sets (a string when the text is no TOML value).
    pub value: toml::Value,
}

impl GridValue {
    /// A value as `--values` / `--set KEY=VALUE` take it: TOML if it is one TOML value, else the text as a
    /// string. The text is trimmed.
    ///
    /// # Errors
    /// A one-line message on empty text, or on text holding several TOML values or lines.
    pub fn parse(text: &str) -> Result<GridValue, String> {
        let text = text.trim();
        if text.is_empty() {
            return Err("an empty value (give the values separated by commas: 0,0.2,0.4)".to_string());
        }
        let value = Override::parse_value(text)?;
        Ok(GridValue { text: text.to_string(), value })
    }
}

/// One scene key of a grid (a dotted path, as `--set` takes it) and its values, in order.
#[derive(Clone, Debug, PartialEq)]
pub struct GridParam {
    /// The dotted scene key, e.g. `material.grey.sigma`.
    pub key: String,
    /// Its values, in the order the grid steps through them.
    pub values: Vec<GridValue>,
}

/// The parameters of a sweep: at least one, each with at least one value, no key twice.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    params: Vec<GridParam>,
    len: usize,
}

impl Grid {
    /// A grid of these parameters, in this order (the first varies slowest).
    ///
    /// # Errors
    /// One line naming the key (and value): no parameter, a key that is no dotted path, a parameter with no
    /// values, a key given twice, more combinations than can be counted.
    pub fn new(params: Vec<GridParam>) -> Result<Grid, String> {
        if params.is_empty() {
            return Err("no parameter to sweep (give --param KEY --values V1,V2,...)".to_string());
        }
        let mut len = 1usize;
        for (index, param) in params.iter().enumerate() {
            let key = &param.key;
            if key.is_empty() || key.split('.').any(str::is_empty) {
                return Err(format!("--param `{}`: not a dotted key path (e.g. material.grey.sigma)", shortened(key)));
            }
            if param.values.is_empty() {
                return Err(format!("--param {key}: no values (give --values V1,V2,... after it)"));
            }
            if params[..index].iter().any(|earlier| earlier.key == *key) {
                return Err(format!("--param {key} is given twice (give each key once, with all its values)"));
            }
            len = len
                .checked_mul(param.values.len())
                .ok_or_else(|| format!("--param {key}: the grid has more combinations than can be counted"))?;
        }
        Ok(Grid { params, len })
    }

    /// The parameters, in the grid's order.
    pub fn params(&self) -> &[GridParam] {
        &self.params
    }

    /// The number of combinations (the product of the value counts).
    pub fn len(&self) -> usize {
        self.len
    }

    /// Never true: a grid has at least one combination (for clippy's `len_without_is_empty`).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Combination `index` (below [`Grid::len`]) in row-major order: the first parameter varies slowest,
    /// the last fastest.
    ///
    /// # Panics
    /// When `index` is not below [`Grid::len`].
    pub fn combination(&self, index: usize) -> Combination {
        let values = self
            .positions(index)
            .into_iter()
            .zip(&self.params)
            .map(|(position, param)| (param.key.clone(), param.values[position].clone()))
            .collect();
        Combination { index, values }
    }

    /// Which value of each parameter combination `index` takes, in the grid's order (row-major: the first
    /// parameter varies slowest).
    ///
    /// # Panics
    /// When `index` is not below [`Grid::len`].
    pub fn positions(&self, index: usize) -> Vec<usize> {
        assert!(index < self.len, "combination {index} of a grid of {}", self.len);
        let mut rest = index;
        let mut positions: Vec<usize> = self
            .params
            .iter()
            .rev()
            .map(|param| {
                let position = rest % param.values.len();
                rest /= param.values.len();
                position
            })
            .collect();
        positions.reverse();
        positions
    }

    /// Every combination in order.
    pub fn combinations(&self) -> Vec<Combination> {
        (0..self.len).map(|index| self.combination(index)).collect()
    }

    /// The short name of parameter `param` for labels and file names: its key's last segment
    /// (`material.grey.kd` -> `kd`), or the whole key when another parameter has the same last segment
    /// (`material.a.kd` and `material.b.kd` keep theirs whole, so that labels and files tell them apart).
    pub fn short_name(&self, param: usize) -> String {
        let last = |key: &str| key.rsplit('.').next().unwrap_or(key).to_string();
        let key = &self.params[param].key;
        let short = last(key);
        let shared = self.params.iter().enumerate().any(|(other, p)| other != param && last(&p.key) == short);
        if shared {
            key.clone()
        } else {
            short
        }
    }
}

/// One combination of a grid's values: the scene of one tile.
#[derive(Clone, Debug, PartialEq)]
pub struct Combination {
    /// Its place in the grid's order.
    pub index: usize,
    /// (key, value) for each parameter, in the grid's order.
    pub values: Vec<(String, GridValue)>,
}

impl Combination {
    /// `--set` overrides that make this combination's scene.
    pub fn overrides(&self) -> Vec<Override> {
        self.values.iter().map(|(key, value)| Override::new(key.clone(), value.value.clone())).collect()
    }

    /// The tile's label: one parameter -> "kd = 0.3"; several -> "kd = 0.3, sigma = 0.2".
    pub fn label(&self, grid: &Grid) -> String {
        let parts: Vec<String> = self
            .values
            .iter()
            .enumerate()
            .map(|(param, (_, value))| format!("{} = {}", grid.short_name(param), value.text))
            .collect();
        parts.join(", ")
    }

    /// The tile's file beside the sheet: one parameter -> SHEET-VALUE.png; several ->
    /// SHEET-kd=0.3-sigma=0.2.png (every value, in the grid's order). Characters other than letters,
    /// digits, '.', '-' and '_' ('=' too, with several parameters) become '_'.
    pub fn tile_path(&self, grid: &Grid, sheet: &Path) -> PathBuf {
        let stem = sheet.file_stem().unwrap_or_default().to_string_lossy();
        let name = match self.values.as_slice() {
            [(_, value)] => file_safe(&value.text, ""),
            values => {
                let parts: Vec<String> = values
                    .iter()
                    .enumerate()
                    .map(|(param, (_, value))| file_safe(&format!("{}={}", grid.short_name(param), value.text), "="))
                    .collect();
                parts.join("-")
            }
        };
        sheet.with_file_name(format!("{stem}-{name}.png"))
    }
}

/// Text as part of a file name: anything but letters, digits, '.', '-', '_' and `also` becomes '_'.
fn file_safe(text: &str, also: &str) -> String {
    text.chars()
        .map(|c| if c.is_ascii_alphanumeric() || "._-".contains(c) || also.contains(c) { c } else { '_' })
        .collect()
}

/// `--shard K/N`: the K-th (1-based) of N fixed, deterministic shares of a grid's combinations:
/// combination i belongs to shard (i % N) + 1, so that every share holds combinations from the whole grid
/// (as long to render as the others, roughly) and N processes (a Slurm job array, GNU parallel) together
/// render each combination exactly once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which share, from 1 to `n`.
    pub k: usize,
    /// How many shares, at least 1.
    pub n: usize,
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(text: &str) -> Result<Shard, String> {
        let text = text.trim();
        let not_k_of_n = || format!("`{}` is not K/N (the K-th of N shares, e.g. 2/8)", shortened(text));
        let (k, n) = text.split_once('/').ok_or_else(not_k_of_n)?;
        let (k, n): (usize, usize) =
            (k.trim().parse().map_err(|_| not_k_of_n())?, n.trim().parse().map_err(|_| not_k_of_n())?);
        if n == 0 {
            return Err(format!("`{text}`: N is the number of shares, at least 1"));
        }
        if k == 0 || k > n {
            return Err(format!("`{text}`: K is 1 to {n} (the K-th of N shares, counted from 1)"));
        }
        Ok(Shard { k, n })
    }
}

impl Shard {
    /// Whether combination `index` belongs to this shard.
    pub fn contains(&self, index: usize) -> bool {
        index % self.n + 1 == self.k
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn param(key: &str, values: &[&str]) -> GridParam {
        GridParam { key: key.to_string(), values: values.iter().map(|v| GridValue::parse(v).unwrap()).collect() }
    }

    fn texts(combination: &Combination) -> Vec<&str> {
        combination.values.iter().map(|(_, value)| value.text.as_str()).collect()
    }

    #[test]
    fn combinations_are_row_major() {
        let grid = Grid::new(vec![param("a.x", &["1", "2"]), param("b.y", &["p", "q", "r"])]).unwrap();
        assert_eq!(grid.len(), 6);
        let combinations = grid.combinations();
        let order: Vec<Vec<&str>> = combinations.iter().map(texts).collect();
        assert_eq!(order, [["1", "p"], ["1", "q"], ["1", "r"], ["2", "p"], ["2", "q"], ["2", "r"]]);
        assert!(combinations.iter().enumerate().all(|(i, c)| c.index == i && *c == grid.combination(i)));
        let three = Grid::new(vec![param("a", &["1", "2"]), param("b", &["3", "4"]), param("c", &["5", "6"])]).unwrap();
        assert_eq!(texts(&three.combination(5)), ["2", "3", "6"]);
        assert_eq!(three.combination(5).values[0].0, "a");
    }

    #[test]
    fn values_are_toml_or_text() {
        let number = GridValue::parse(" 0.25 ").unwrap();
        assert_eq!((number.text.as_str(), number.value), ("0.25", toml::Value::Float(0.25)));
        assert_eq!(GridValue::parse("phong").unwrap().value, toml::Value::String("phong".into()));
        assert_eq!(GridValue::parse("[1, 2, 3]").unwrap().value.as_array().map(Vec::len), Some(3));
        let overrides = Grid::new(vec![param("material.grey.kd", &["0.3"])]).unwrap().combination(0).overrides();
        assert_eq!(overrides, [Override::new("material.grey.kd", 0.3)]);
    }

    #[test]
    fn bad_values_and_grids_are_one_line_naming_them() {
        for empty in ["", "  "] {
            assert!(GridValue::parse(empty).unwrap_err().contains("empty"));
        }
        assert!(GridValue::parse("1\nb = 2").unwrap_err().contains("holds more than one value"));
        assert!(Grid::new(vec![]).unwrap_err().contains("--param"));
        let none = Grid::new(vec![param("a.b", &[])]).unwrap_err();
        assert!(none.contains("a.b") && none.contains("no values"), "{none}");
        let twice = Grid::new(vec![param("a.b", &["1"]), param("a.b", &["2"])]).unwrap_err();
        assert!(twice.contains("a.b") && twice.contains("twice"), "{twice}");
        assert!(Grid::new(vec![param("a..b", &["1"])]).unwrap_err().contains("a..b"));
        for message in [none, twice] {
            assert_eq!(message.lines().count(), 1, "{message}");
        }
    }

    #[test]
    fn short_names_keep_the_whole_key_when_last_segments_collide() {
        let grid = Grid::new(vec![
            param("material.a.kd", &["1"]),
            param("material.b.kd", &["2"]),
            param("material.b.sigma", &["3"]),
        ])
        .unwrap();
        let names: Vec<String> = (0..3).map(|i| grid.short_name(i)).collect();
        assert_eq!(names, ["material.a.kd", "material.b.kd", "sigma"]);
        assert_eq!(grid.combination(0).label(&grid), "material.a.kd = 1, material.b.kd = 2, sigma = 3");
    }

    #[test]
    fn labels_and_tile_paths() {
        let sheet = Path::new("out/sweep.png");
        let one = Grid::new(vec![param("material.grey.kd", &["0.3", "[1, 2]", "a/b c"])]).unwrap();
        let paths: Vec<PathBuf> = one.combinations().iter().map(|c| c.tile_path(&one, sheet)).collect();
        assert_eq!(paths, ["out/sweep-0.3.png", "out/sweep-_1__2_.png", "out/sweep-a_b_c.png"].map(PathBuf::from));
        assert_eq!(one.combination(0).label(&one), "kd = 0.3");
        let two =
            Grid::new(vec![param("material.grey.kd", &["0.3"]), param("material.matte.sigma", &["0.2", "x=y z"])])
                .unwrap();
        assert_eq!(two.combination(0).label(&two), "kd = 0.3, sigma = 0.2");
        assert_eq!(two.combination(0).tile_path(&two, sheet), PathBuf::from("out/sweep-kd=0.3-sigma=0.2.png"));
        assert_eq!(two.combination(1).tile_path(&two, sheet), PathBuf::from("out/sweep-kd=0.3-sigma=x=y_z.png"));
    }

    #[test]
    fn shards_partition_the_combinations() {
        for n in 1..=7 {
            let shards: Vec<Shard> = (1..=n).map(|k| format!("{k}/{n}").parse().unwrap()).collect();
            for index in 0..50 {
                let owners = shards.iter().filter(|shard| shard.contains(index)).count();
                assert_eq!(owners, 1, "combination {index} of {n} shards");
            }
        }
        let second: Vec<usize> = (0..10).filter(|&i| Shard { k: 2, n: 3 }.contains(i)).collect();
        assert_eq!(second, [1, 4, 7]);
        assert_eq!(" 1/1 ".parse(), Ok(Shard { k: 1, n: 1 }));
    }

    #[test]
    fn bad_shards_say_what_k_and_n_are() {
        for (text, needle) in [("0/2", "K is 1 to 2"), ("3/2", "K is 1 to 2"), ("1/0", "N is"), ("x", "not K/N")] {
            let message = text.parse::<Shard>().unwrap_err();
            assert!(message.contains(needle) && message.contains(text), "{text}: {message}");
        }
        for text in ["", "1/", "/2", "-1/2", "1/2/3", "a/b"] {
            assert!(text.parse::<Shard>().is_err(), "{text:?}");
        }
    }
}
