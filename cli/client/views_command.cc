// `omniview views list|get|create|update|delete`.
#include <algorithm>
#include <cctype>
#include <iostream>
#include <map>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/client/view_spec_proto.h"
#include "cli/client/views_save.h"
#include "core/io/yaml_reader.h"
#include "core/view/view_spec.h"

namespace omniview::cli {
namespace {

const std::string kViewsHelp = std::string(R"(usage: omniview views list
       omniview views get VIEW
       omniview views create --file VIEW.yaml [--set KEY=VALUE ...]
       omniview views create --set name=NAME --set type=TYPE [--set KEY=VALUE ...]
       omniview views update [VIEW] [--file VIEW.yaml] [--set KEY=VALUE ...]
       omniview views delete VIEW [VIEW ...]
       omniview views save FILE.yaml

Manages omniviewd's views (create, update and delete need an operator token).

  list      the views, one line each
  get       one view in the view YAML schema (pipe it into a file to edit and update)
  create    new views from a view YAML file (one view, or 'views: [...]': each is
            created) and/or --set keys; unset keys take the schema's defaults
  update    change only the keys the file or --set give; with a file and no VIEW, each
            view in the file updates the view of its name; 'name' in --set renames
  delete    remove views
  save      every current view into FILE.yaml (replaced if it exists), which the daemon
            loads at start with 'views_file: FILE.yaml' in its config: views created or
            changed at run time survive a restart

  --file FILE        a view YAML file, the schema of 'omniview render --view' and the
                     daemon config's 'views:'
  --set KEY=VALUE    one field (repeatable); applied after --file

)") + settable_keys_help() +
                          "\n" + connection_help();

std::string type_name(const v1::ViewSpec& s) {
  try {
    return to_string(from_proto(s.type(), view_label(s.name())));
  } catch (const std::invalid_argument&) {
    return "type " + std::to_string(static_cast<int>(s.type()));
  }
}

// The field of view that matters for the view's type, for the list.
std::string fov_text(const v1::ViewSpec& s) {
  switch (s.type()) {
    case v1::PERSPECTIVE:
    case v1::BIRDSEYE:
      return fixed(s.hfov_deg(), 1);
    case v1::FISHEYE:
      return fixed(s.fov_deg(), 1);
    case v1::CYLINDRICAL:
      return fixed(s.azimuth_span_deg(), 0) + "x" + fixed(s.vfov_deg(), 0);
    default:
      return fixed(s.azimuth_span_deg(), 0);
  }
}

// `views update --file` takes only the keys to change, but the view schema needs `type`:
// a view map without one gets the type the view has now (VIEW, or the map's `name`).
std::vector<v1::ViewSpec> load_update_file(Connection& connection, const std::string& file, const std::string& target) {
  const auto reader = YamlReader::from_file(file);
  YAML::Node root = reader.root();
  std::vector<YAML::Node> maps;
  if (root.IsMap() && root["views"] && root["views"].IsSequence()) {
    for (auto n : root["views"]) maps.push_back(n);
  } else if (root.IsMap()) {
    maps.push_back(root);
  }
  for (auto& n : maps) {
    if (!n.IsMap() || n["type"]) continue;
    const std::string name = !target.empty() ? target : (n["name"] && n["name"].IsScalar() ? n["name"].Scalar() : "");
    if (name.empty()) continue;  // the parser says what is missing
    v1::GetViewRequest get;
    get.set_name(name);
    v1::View view;
    grpc::ClientContext context;
    connection.prepare(context, true);
    connection.check(connection.stub().GetView(&context, get, &view), view_label(name));
    std::string type = v1::ViewType_Name(view.spec().type());
    std::transform(type.begin(), type.end(), type.begin(), [](unsigned char c) { return std::tolower(c); });
    n["type"] = type;
  }
  return views_from_yaml(reader);
}

// Specs from --file and --set: one per view in the file, or one from --set alone. For an
// update, `connection` fills in the types a partial file leaves out.
std::vector<v1::ViewSpec> specs_from_args(const Args& args, Connection* connection = nullptr,
                                          const std::string& target = "") {
  std::vector<v1::ViewSpec> specs;
  if (args.has("file")) {
    for (const auto& file : args.all("file")) {
      for (auto& spec : connection ? load_update_file(*connection, file, target) : load_view_file(file)) {
        specs.push_back(std::move(spec));
      }
    }
  } else {
    specs.emplace_back();
  }
  if (specs.size() > 1 && !args.all("set").empty()) {
    for (const auto& s : args.all("set")) {
      if (s.rfind("name=", 0) == 0) throw UsageError("--set name=... with several views would give them one name");
    }
  }
  for (auto& spec : specs) {
    for (const auto& assignment : args.all("set")) apply_setting(assignment, spec);
  }
  return specs;
}

int list(Connection& connection) {
  v1::ListViewsResponse response;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().ListViews(&context, v1::ListViewsRequest(), &response), "views");
  if (response.views().empty()) {
    std::cout << "no views (create one with 'omniview views create --file VIEW.yaml')\n";
    return 0;
  }
  Table table({"VIEW", "TYPE", "SIZE", "SOURCE", "FRAME", "PAN", "TILT", "FOV", "REVISION"});
  for (const auto& v : response.views()) {
    const auto& s = v.spec();
    table.add({s.name(), type_name(s), std::to_string(s.width()) + "x" + std::to_string(s.height()), s.source(),
               s.frame().empty() ? "-" : s.frame(), fixed(s.yaw_deg(), 1), fixed(s.pitch_deg(), 1), fov_text(s),
               std::to_string(v.revision())});
  }
  table.print(std::cout);
  return 0;
}

int get(Connection& connection, const std::string& name) {
  v1::GetViewRequest request;
  request.set_name(name);
  v1::View view;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().GetView(&context, request, &view), view_label(name));
  // YAML first so the output can be saved and given back to `views update --file`.
  std::cout << view.yaml();
  if (!view.yaml().empty() && view.yaml().back() != '\n') std::cout << "\n";
  std::cout << "# revision: " << view.revision() << "\n";
  if (!view.intrinsics().empty()) {
    std::cout << "# intrinsics [fx, fy, cx, cy]:";
    for (double k : view.intrinsics()) std::cout << " " << fixed(k, 3);
    std::cout << "\n";
  }
  const auto& p = view.pose();
  std::cout << "# pose in " << view.robot_frame() << ": xyz " << fixed(p.translation().x(), 3) << " "
            << fixed(p.translation().y(), 3) << " " << fixed(p.translation().z(), 3) << ", q_wxyz " << fixed(p.qw(), 5)
            << " " << fixed(p.qx(), 5) << " " << fixed(p.qy(), 5) << " " << fixed(p.qz(), 5) << "\n";
  return 0;
}

// A view pointed where no camera looks is mostly black: say so now, not when someone
// wonders at a black picture.
void warn_on_low_coverage(Connection& connection, const std::vector<v1::View>& created_views) {
  std::vector<v1::ViewSpec> created;
  for (const auto& v : created_views) created.push_back(v.spec());
  v1::Status status;
  grpc::ClientContext context;
  connection.prepare(context, true);
  if (!connection.stub().GetStatus(&context, v1::GetStatusRequest(), &status).ok()) return;  // the views exist
  // Only once the view's source delivers: a robot not yet connected has no cameras.
  std::map<std::string, bool> delivering;
  for (const auto& s : status.sources()) delivering[s.name()] = s.connected() && s.frames() > 0;
  for (const auto& v : status.views()) {
    for (const auto& spec : created) {
      if (v.name() != spec.name() || !delivering[spec.source()]) continue;
      const std::string warning = low_coverage_warning(v.name(), v.coverage());
      if (!warning.empty()) std::cerr << "warning: " << warning << "\n";
    }
  }
}

int create(Connection& connection, const Args& args) {
  if (!args.has("file") && args.all("set").empty()) throw UsageError("create needs --file VIEW.yaml or --set keys");
  const auto specs = specs_from_args(args);
  for (const auto& spec : specs) {
    if (!spec.has_name() || spec.name().empty()) {
      throw UsageError("a view to create needs a name: add 'name:' to the file or --set name=NAME");
    }
  }
  std::vector<v1::View> created;
  for (const auto& spec : specs) {
    v1::CreateViewRequest request;
    *request.mutable_spec() = spec;
    v1::View view;
    grpc::ClientContext context;
    connection.prepare(context, true);
    connection.check(connection.stub().CreateView(&context, request, &view), view_label(spec.name()));
    std::cout << "created view '" << view.spec().name() << "' (" << type_name(view.spec()) << ", "
              << view.spec().width() << "x" << view.spec().height() << ", "
              << (view.spec().fusion() == v1::NEAREST_CENTRE ? "nearest" : "blend") << ", revision "
              << view.revision() << ")\n";
    created.push_back(view);
  }
  warn_on_low_coverage(connection, created);
  return 0;
}

int update(Connection& connection, const Args& args) {
  if (!args.has("file") && args.all("set").empty()) throw UsageError("update needs --file VIEW.yaml or --set keys");
  const auto& positional = args.positional();
  if (positional.size() > 2) throw UsageError("unexpected argument '" + positional[2] + "'");
  std::vector<std::pair<std::string, v1::ViewSpec>> updates;  // target name, changes
  if (positional.size() == 2) {
    auto specs = specs_from_args(args, &connection, positional[1]);
    if (specs.size() != 1) throw UsageError("the file holds several views: leave out VIEW to update each by name");
    updates.emplace_back(positional[1], specs[0]);
  } else {
    if (!args.has("file")) throw UsageError("missing VIEW (the view to update)");
    for (const auto& spec : specs_from_args(args, &connection)) {
      if (!spec.has_name()) throw UsageError("a view in the file has no name: give VIEW, or add 'name:'");
      updates.emplace_back(spec.name(), spec);
    }
  }
  for (const auto& [name, spec] : updates) {
    v1::UpdateViewRequest request;
    request.set_name(name);
    *request.mutable_set() = spec;
    // The view's own name in its file is no rename.
    if (spec.has_name() && spec.name() == name) request.mutable_set()->clear_name();
    v1::View view;
    grpc::ClientContext context;
    connection.prepare(context, true);
    connection.check(connection.stub().UpdateView(&context, request, &view), view_label(name));
    std::cout << "updated view '" << view.spec().name() << "' (revision " << view.revision() << ")\n";
  }
  return 0;
}

int remove(Connection& connection, const Args& args) {
  const auto& positional = args.positional();
  if (positional.size() < 2) throw UsageError("missing VIEW (the view to delete)");
  for (size_t i = 1; i < positional.size(); ++i) {
    v1::DeleteViewRequest request;
    request.set_name(positional[i]);
    v1::DeleteViewResponse response;
    grpc::ClientContext context;
    connection.prepare(context, true);
    connection.check(connection.stub().DeleteView(&context, request, &response), view_label(positional[i]));
    std::cout << "deleted view '" << positional[i] << "'\n";
  }
  return 0;
}

}  // namespace

int views_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {}, {"file", "set"}, kViewsHelp);
  if (!args) return 0;
  const auto& positional = args->positional();
  if (positional.empty()) throw UsageError("missing subcommand: list, get, create, update, delete or save (see --help)");
  const std::string& sub = positional[0];
  const bool edits = sub == "create" || sub == "update";
  if (!edits && (args->has("file") || args->has("set"))) {
    throw UsageError("--file and --set belong to 'views create' and 'views update'");
  }
  if (sub != "list" && sub != "get" && !edits && sub != "delete" && sub != "save") {
    throw UsageError("unknown subcommand '" + sub + "': list, get, create, update, delete or save");
  }
  if (sub == "list") expect_positional(*args, 1, "");
  if (sub == "get") expect_positional(*args, 2, "VIEW");
  if (sub == "create") expect_positional(*args, 1, "");
  if (sub == "save") expect_positional(*args, 2, "FILE.yaml");

  Connection connection(connection_options(*args));
  if (sub == "list") return list(connection);
  if (sub == "get") return get(connection, positional[1]);
  if (sub == "create") return create(connection, *args);
  if (sub == "update") return update(connection, *args);
  if (sub == "save") {
    const int saved = save_views(connection, positional[1]);
    std::cout << "saved " << saved << " view" << (saved == 1 ? "" : "s") << " to " << positional[1] << "\n";
    return 0;
  }
  return remove(connection, *args);
}

}  // namespace omniview::cli
