// runCli (cli_main.hpp): the exit statuses and messages every oas tool shares.
#include "apps/cli_main.hpp"

#include <exception>
#include <iostream>
#include <new>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "oas/pattern.hpp"
#include "scene/scene.hpp"

namespace oas {

int runCli(std::string_view tool, CLI::App& app, int argc, char** argv, const std::function<int()>& body,
           const std::function<std::string()>& outOfMemory)
{
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << tool << ": error: " << e.what() << "\nrun with --help for the options\n";
        return 2;
    }
    try {
        return body();
    } catch (const scene::SceneError& e) {
        std::cerr << tool << ": error: " << e.what() << "\n";
        return 2;
    } catch (const InvalidArgument& e) {
        std::cerr << tool << ": error: " << e.what() << "\n";
        return 2;
    } catch (const std::invalid_argument& e) {
        std::cerr << tool << ": error: " << e.what() << "\n";
        return 2;
    } catch (const std::bad_alloc&) {
        std::cerr << tool << ": error: " << (outOfMemory ? outOfMemory() : std::string("out of memory")) << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << tool << ": error: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace oas
