#include "cli/client/views_save.h"

#include <cerrno>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace omniview::cli {

int save_views(Connection& connection, const std::string& file) {
  v1::ListViewsResponse response;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().ListViews(&context, v1::ListViewsRequest(), &response), "views");

  YAML::Emitter out;
  out.SetDoublePrecision(12);  // as the daemon writes a view's YAML: 0.42, not 0.41999999999999998
  out << YAML::BeginMap << YAML::Key << "views" << YAML::Value << YAML::BeginSeq;
  for (const auto& view : response.views()) {
    // Each view's definition in the view YAML schema, as the daemon itself wrote it.
    out << YAML::Load(view.yaml());
  }
  out << YAML::EndSeq << YAML::EndMap;
  if (!out.good()) throw std::runtime_error("cannot write the views as YAML: " + out.GetLastError());

  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &tm);
  // Written beside the target and renamed over it: a daemon starting meanwhile reads the
  // old file or the new one, never half of one.
  const std::filesystem::path target(file), temporary(file + ".tmp");
  if (const auto folder = target.parent_path(); !folder.empty() && !std::filesystem::is_directory(folder)) {
    throw std::runtime_error("cannot write '" + file + "': the folder '" + folder.string() + "' does not exist");
  }
  {
    std::ofstream f(temporary, std::ios::trunc);
    f << "# The views of omniviewd at " << connection.options().server << ", saved " << stamp
      << " by 'omniview views save'.\n"
      << "# Load them at start with 'views_file: " << target.filename().string()
      << "' in the daemon's config (a view here replaces the config's view of the same name).\n"
      << out.c_str() << "\n";
    f.close();
    if (!f) throw std::runtime_error("cannot write '" + temporary.string() + "': " + std::strerror(errno));
  }
  std::error_code ec;
  std::filesystem::rename(temporary, target, ec);
  if (ec) throw std::runtime_error("cannot write '" + file + "': " + ec.message());
  return response.views_size();
}

}  // namespace omniview::cli
