// `fredholm info SCENE`: what a scene holds and which effects it compiles, with the reason for each, without
// rendering (no Vulkan device needed).
#pragma once
#include <filesystem>

#include "render/settings.h"

namespace CLI {
class App;
}

namespace fh {

struct InfoCommand {
    std::filesystem::path scene;
    RenderSettings settings;  // --env/--background/--variant/--instancing and --force/--disable-effect
    bool json = false;        // --json: the same as one JSON object on stdout
};

void add_info_options(CLI::App& app, InfoCommand& command);
int run_info(const InfoCommand& command);

}  // namespace fh
