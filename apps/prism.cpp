// The prism command. Subcommands live in apps/<name>_command.cpp.
#include <cstdio>

#include <CLI/CLI.hpp>

#include "apps/batch_command.h"
#include "apps/boids_command.h"
#include "apps/compare_command.h"
#include "apps/diff_command.h"
#include "apps/info_command.h"
#include "apps/render_command.h"
#include "apps/usage.h"
#include "renderer/version.h"

int main(int argc, char** argv) {
  CLI::App app{"prism: a CPU ray tracer for glTF scenes, built on Embree", "prism"};
  app.set_version_flag("--version", std::string("prism ") + prism::kVersion);
  app.require_subcommand(1);
  prism::RenderOptions render_options;
  CLI::App* render = prism::add_render_command(app, &render_options);
  prism::DiffOptions diff_options;
  CLI::App* diff = prism::add_diff_command(app, &diff_options);
  prism::CompareOptions compare_options;
  CLI::App* compare = prism::add_compare_command(app, &compare_options);
  prism::InfoOptions info_options;
  CLI::App* info = prism::add_info_command(app, &info_options);
  prism::BatchCommandOptions batch_options;
  CLI::App* batch = prism::add_batch_command(app, &batch_options);
  prism::BoidsOptions boids_options;
  CLI::App* boids = prism::add_boids_command(app, &boids_options);
  std::string help_command;
  CLI::App* help = prism::add_help_command(app, &help_command);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::Success&) {
    return 0;  // a flag that did its work as it was parsed (compare --clear-cache)
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // the same, having printed its error
  } catch (const CLI::ParseError& e) {
    // Usage errors exit with 2, as most command-line tools do.
    std::fprintf(stderr, "prism: error: %s (see prism %s--help)\n",
                 prism::describe_parse_error(app, e).c_str(),
                 render->parsed()    ? "render "
                 : diff->parsed()    ? "diff "
                 : compare->parsed() ? "compare "
                 : info->parsed()    ? "info "
                 : batch->parsed()   ? "batch "
                 : boids->parsed()   ? "boids "
                                     : "");
    return 2;
  }
  if (render->parsed()) {
    render_options.argv.assign(argv, argv + argc);
    return prism::run_render(render_options);
  }
  if (diff->parsed()) return prism::run_diff(diff_options);
  if (compare->parsed()) return prism::run_compare(compare_options);
  if (info->parsed()) return prism::run_info(info_options);
  if (batch->parsed()) return prism::run_batch(batch_options);
  if (boids->parsed()) return prism::run_boids(boids_options);
  if (help->parsed()) return prism::run_help(app, help_command);
  return 2;
}
