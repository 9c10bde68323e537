// Registers `carom view`: the viewer where this build has it (SDL2, OpenGL
// and Dear ImGui found), otherwise a subcommand that says what is missing.
#include <memory>

#include "app/commands.h"
#ifdef CAROM_HAVE_VIEWER
#include "app/viewer/viewer.h"
#endif

namespace carom::app {

std::function<int()> addViewCommand(CLI::App& app) {
#ifdef CAROM_HAVE_VIEWER
    auto options = std::make_shared<viewer::ViewOptions>();
    CLI::App* view = app.add_subcommand("view", "Watch and play with a scene in a window (SDL2 + OpenGL)");
    viewer::addViewOptions(*view, *options);
    return [options] { return viewer::runViewer(*options); };
#else
    app.add_subcommand("view", "Watch a scene in a window (not available: built without SDL2/OpenGL/ImGui)")
        ->allow_extras();
    return []() -> int {
        throw Error(
            "this carom was built without the viewer (SDL2, OpenGL or Dear ImGui were not found at build "
            "time); install libsdl2-dev, libimgui-dev and libstb-dev and rebuild, or use `carom run`");
    };
#endif
}

}  // namespace carom::app
