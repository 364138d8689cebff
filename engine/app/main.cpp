// The fredholm command line: sub-commands render, merge, view, converge, bench and info; one clear error line and a
// non-zero exit on any failure (1: the scene, the device or a file; 2: bad usage).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "app/bench_command.h"
#include "app/converge_command.h"
#include "app/info_command.h"
#include "app/merge_command.h"
#include "app/render_command.h"
#include "app/viewer_command.h"

int main(int argc, char** argv) {
    CLI::App app{"Fredholm: an unbiased path tracer for glTF 2.0 on Vulkan compute"};
    app.require_subcommand(1);
    fh::RenderCommand render;
    fh::add_render_options(*app.add_subcommand("render", "render a glTF scene to OpenEXR"), render);
    fh::BenchCommand bench;
    fh::add_bench_options(*app.add_subcommand("bench", "time the Cornell box at 256x256 and 512x512"), bench);
    fh::ConvergeCommand converge;
    fh::add_converge_options(*app.add_subcommand("converge", "error against render time at doubling spp, as a report"),
                             converge);
    fh::InfoCommand info;
    fh::add_info_options(*app.add_subcommand("info", "scene statistics and the effects it compiles, with why"), info);
    fh::MergeCommand merge;
    fh::add_merge_options(*app.add_subcommand("merge", "join parts of a render (--samples, --crop) bit-exactly"), merge);
    fh::ViewCommand view;
    fh::add_view_options(*app.add_subcommand("view", "interactive viewer: progressive path tracing in a window"), view);
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
        return fh::run_bench(bench);
    } catch (const CLI::ParseError& e) {  // an option checked against others once all are known (e.g. --crop)
        std::fprintf(stderr, "fredholm: usage error: %s (see fredholm --help)\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fredholm: error: %s\n", e.what());
        return 1;
    }
}
