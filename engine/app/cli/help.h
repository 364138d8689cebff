// What `fredholm COMMAND --help` shows: the options a user needs, in groups, one line each, and an example; the
// measurement and diagnostic switches stay accepted but are listed only by --help-all (and always by bench).
#pragma once
#include <set>
#include <string>

namespace CLI {
class App;
}

namespace fh {

// True when argv asks for --help-all; that word is then replaced by --help, so the parser shows help as usual.
bool take_help_all(int argc, char** argv);

// Puts each of the command's options in its help group (one table for every command, in help.cpp), hides the
// measurement and diagnostic switches unless show_all, and ends the help with the example line.
// Options named in keep_group (long names without dashes) keep the group their command gave them.
void arrange_help(CLI::App& command, bool show_all, const std::string& example,
                  const std::set<std::string>& keep_group = {});

}  // namespace fh
