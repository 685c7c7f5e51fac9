#pragma once
// The frame every oas tool's main() shares: parse the command line, run the tool, and turn what
// went wrong into the exit status and the one-line message each tool documents, so that a script
// (scripts/cluster.py, the tests) can tell "you asked for something invalid" (2) from "it failed"
// (1) the same way for every tool.
//
//   int main(int argc, char** argv)
//   {
//       CLI::App app{"oas-foo: ..."};
//       ... app.add_option(...) ...
//       return oas::runCli("oas-foo", app, argc, argv, [&] { ...; return 0; });
//   }
#include <functional>
#include <string>
#include <string_view>

namespace CLI {
class App;
}

namespace oas {

/// Parses argv into `app`, then returns body(). What escapes, and the status it becomes:
///   --help                      CLI11's help on stdout; 0
///   a command-line error        "<tool>: error: <what>" and "run with --help for the options"
///                               on stderr; 2
///   oas::scene::SceneError, oas::InvalidArgument, std::invalid_argument (a bad scene, option
///   value or request)           "<tool>: error: <what>" on stderr; 2
///   std::bad_alloc              "<tool>: error: " + outOfMemory() (default "out of memory"); 1
///   any other std::exception    "<tool>: error: <what>"; 1
/// outOfMemory runs once body's stack has unwound, so it may say how much was asked for.
int runCli(std::string_view tool, CLI::App& app, int argc, char** argv, const std::function<int()>& body,
           const std::function<std::string()>& outOfMemory = {});

}  // namespace oas
