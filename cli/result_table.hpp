// What a run measured, as a short table on the terminal (semlb surrogate, replay --workload and sweep end with it).
#pragma once
#include <string>
#include <vector>

namespace semlb::cli {

// The rows of the results CSV at `csv_path` as one line per policy and P when the CSV has those columns (other axes,
// such as workloads, pooled), else per axis of `keys` whose column varies; first-seen order. Each line: the mean of
// each measured column the CSV has (imbalance in %, migration, loop / wall / compute seconds, ...; at most five), "mean
// ± sd" where it pools several rows (seeds, launches, workloads), and n. Knob columns (POLICY.KEY) make a setting;
// of several settings the line shows the one with the least mean of the first measured column. At most `max_groups`
// lines, then a line saying how many more the CSV holds. Empty when the CSV has no measured column or no row.
std::string result_table(const std::string& csv_path, const std::vector<std::string>& keys, size_t max_groups = 40);

// One result as the same table: `keys` and `values` (name, value) of one run.
std::string result_row(const std::vector<std::pair<std::string, std::string>>& keys,
                       const std::vector<std::pair<std::string, double>>& values);

}  // namespace semlb::cli
