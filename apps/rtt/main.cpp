// The `rtt` program. Errors of any kind end here as one line on stderr and a non-zero exit:
// rtt::Error (bad input), CLI11 parse errors (bad options), std::bad_alloc.
#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "cli_hints.h"
#include "commands.h"
#include "mpi_render.h"
#include "rtt/error.h"
#include "rtt/version.h"

namespace {

int fail(std::string message, int code) {
    for (char& c : message)
        if (c == '\n' || c == '\r') c = ' ';
    // Under mpirun a failure on any rank stops every rank, naming the rank.
    if (rtt::cli::mpi_distributed()) rtt::cli::mpi_abort(message);
    std::fprintf(stderr, "rtt: error: %s\n", message.c_str());
    rtt::cli::mpi_finish();
    return code;
}

}  // namespace

int main(int argc, char** argv) {
    rtt::cli::mpi_start(argc, argv);
    CLI::App app{
        "rtt: ray tracing with SIMD shaft culling (Dmitriev, Havran, Seidel 2004).\n"
        "Without a subcommand, renders the built-in scene 'room' to room.png and prints\n"
        "the statistics."};
    app.name("rtt");
    app.require_subcommand(0, 1);
    app.set_version_flag("--version", std::string("rtt ") + rtt::version_string);
    rtt::cli::add_render_command(app);
    rtt::cli::add_info_command(app);
    rtt::cli::add_scenes_command(app);
    rtt::cli::add_bench_command(app);
#ifdef RTT_HAVE_VIEWER
    rtt::cli::add_view_command(app);
#endif
    try {
        app.parse(argc, argv);  // runs the chosen subcommand's callback
        if (app.get_subcommands().empty()) rtt::cli::run_default_job();
        rtt::cli::mpi_finish();
        return 0;
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) {  // --help, --version
            rtt::cli::mpi_finish();
            return rtt::cli::mpi_rank() == 0 ? app.exit(e) : 0;
        }
        return fail(std::string(e.what()) + "." + rtt::cli::hint_for(app, e), 2);
    } catch (const rtt::Error& e) {
        return fail(e.what(), 1);
    } catch (const std::bad_alloc&) {
        return fail("out of memory", 1);
    } catch (const std::exception& e) {
        return fail(e.what(), 1);
    }
}
