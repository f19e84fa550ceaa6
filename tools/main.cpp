#include "tools/bsdfCommand.h"
int main(int argc, char** argv) {
    CLI::App app{"principled"};
    int code = 0;
    principled::tools::addBsdfCommands(app, &code);
    CLI11_PARSE(app, argc, argv);
    return code;
}
