// The fredholm command line: sub-commands render, merge, compare, view, converge, bench and info; one clear error line and a
// non-zero exit on any failure (1: the scene, the device or a file; 2: bad usage).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <set>
#include <string>

#include "app/bench/bench_command.h"
#include "app/cli/help.h"
#include "app/converge/converge_command.h"
#include "app/info/info_command.h"
#include "app/compare/compare_command.h"
#include "app/merge/merge_command.h"
#include "app/render/render_command.h"
#include "app/view/viewer_command.h"

int main(int argc, char** argv) {
    CLI::App app{"Fredholm: an unbiased path tracer for glTF 2.0 on Vulkan compute"};
    app.require_subcommand(1);
    app.footer("Example: fredholm render scenes/cornell.gltf -o cornell.exr --png cornell.png\n"
               "Each command's --help lists its options; --help-all adds the measurement and diagnostic switches.");
    const bool help_all = fh::take_help_all(argc, argv);
    // Each command: its options, then its help arranged (bench lists every switch: it is for measurement).
    auto command = [&](const char* name, const char* what, auto& options, auto add_options, const char* example,
                       std::set<std::string> keep_group = {}) {
        CLI::App* sub = app.add_subcommand(name, what);
        add_options(*sub, options);
        fh::arrange_help(*sub, help_all || std::string(name) == "bench", example, keep_group);
    };
    fh::RenderCommand render;
    command("render", "render a glTF scene to OpenEXR", render, fh::add_render_options,
            "fredholm render scenes/cornell.gltf -o cornell.exr --png cornell.png --spp 256");
    fh::BenchCommand bench;
    command("bench", "time the Cornell box at 256x256 and 512x512", bench, fh::add_bench_options,
            "fredholm bench scenes/cornell.gltf --sizes 256 --spp 16 --repeats 5");
    fh::ConvergeCommand converge;
    command("converge", "error against render time at doubling spp, as a report", converge, fh::add_converge_options,
            "fredholm converge scenes/cornell.gltf -o report --two-seeds --vary light-sampler=tree,power");
    fh::InfoCommand info;
    command("info", "scene statistics and the effects it compiles, with why", info, fh::add_info_options,
            "fredholm info scenes/cornell.gltf");
    fh::MergeCommand merge;
    command("merge", "join parts of a render (--samples, --crop) bit-exactly", merge, fh::add_merge_options,
            "fredholm merge parts/part_*.exr -o cornell.exr --png cornell.png");
    fh::CompareCommand compare;
    command("compare", "do two renders differ beyond their noise? (exit 0 same, 1 differs, 2 bad input)", compare,
            fh::add_compare_options, "fredholm compare new.exr golden.exr --heatmap diff.png");
    fh::ViewCommand view;
    command("view", "interactive viewer: progressive path tracing in a window", view, fh::add_view_options,
            "fredholm view scenes/cornell.gltf --env scenes/environments/courtyard.exr", {"frames"});
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "fredholm: usage error: %s (see fredholm --help)\n", e.what());
        return 2;
    }
    try {
        if (app.got_subcommand("render")) return fh::run_render(render);
        if (app.got_subcommand("view")) return fh::run_view(view);
        if (app.got_subcommand("converge")) return fh::run_converge(converge);
        if (app.got_subcommand("info")) return fh::run_info(info);
        if (app.got_subcommand("merge")) return fh::run_merge(merge);
        if (app.got_subcommand("compare")) return fh::run_compare(compare);
        return fh::run_bench(bench);
    } catch (const CLI::ParseError& e) {  // an option checked against others once all are known (e.g. --crop)
        std::fprintf(stderr, "fredholm: usage error: %s (see fredholm --help)\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fredholm: error: %s\n", e.what());
        return 1;
    }
}
