// The "train" runner: one training run per job; its rows are the run's validation log (held-out
// imbalance and migration against steps and wall time). Job keys are training settings (see
// surrogate/train/config.hpp); `config` names a YAML file.
#include <filesystem>
#include <fstream>
#include <mutex>

#include "common/cleanup.hpp"
#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "runner.hpp"
#include "trainer_module.hpp"

namespace semlb::experiments {
namespace {

class TrainRunner final : public Runner {
 public:
  std::vector<std::string> columns() const override {
    return {"step",
            "wall_seconds",
            "loss",
            "lr",
            "temperature",
            "val_imbalance",
            "val_migration",
            "reactive_imbalance",
            "reactive_migration"};
  }

  bool measures_time() const override { return true; }  // wall_seconds column

  void check(const Job& job, const std::string& manifest, const RunOptions& o) const override {
    config(job, manifest, o.base_dir);
  }

  std::vector<std::vector<std::string>> run(const Job& job, const RunOptions& options) const override {
    const auto c = config(job, "", options.base_dir);
    const auto tmp = std::filesystem::temp_directory_path();
    static std::once_flag swept;  // the folders of sweeps that died by SIGKILL, once per process
    std::call_once(swept, [&] { remove_stale_run_folders(tmp.string(), "semlb_train_runner_"); });
    const auto dir = tmp / ("semlb_train_runner_" + std::to_string(::getpid()) + "_" +
                            std::to_string(std::hash<std::string>{}(trainer().to_yaml(c))));
    std::filesystem::create_directories(dir);
    register_cleanup_path(dir.string());  // a signal's cleanup removes it (common/cleanup.hpp)
    struct Remove {                       // and so does every way out of this function
      std::filesystem::path dir;
      ~Remove() {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
        unregister_cleanup_path(dir.string());
      }
    } remove{dir};
    train::TrainOptions o;
    o.out = (dir / "weights.h5").string();
    o.log = (dir / "log.csv").string();
    o.progress = false;
    trainer().run_training(c, o);
    std::vector<std::vector<std::string>> rows;
    std::ifstream in(o.log);
    std::string line;
    std::getline(in, line);  // header: same columns as columns()
    while (std::getline(in, line)) rows.push_back(split(line, ','));
    return rows;
  }

 private:
  static train::TrainConfig config(const Job& job, const std::string& manifest, const std::string& base_dir) {
    std::string file;
    std::vector<std::string> sets;
    for (const auto& [k, s] : job.settings) {
      if (k == "config")
        file = resolve_path(base_dir, s.value);
      else
        sets.push_back(k + "=" + s.value);
    }
    try {
      return trainer().load_train_config(file, sets);
    } catch (const InputError& e) {
      throw InputError(manifest + ": " + e.what());
    }
  }
};

const Registrar<RunnerInfo> registrar("train", {[] { return std::make_unique<TrainRunner>(); }});

}  // namespace
}  // namespace semlb::experiments
