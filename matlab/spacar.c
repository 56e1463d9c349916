/*
 * spacar.c: a MEX gateway with SPACAR's calling form, spacar(mode, file), that runs
 * flexmbd's `flexmbd spacar MODE FILE` and so writes the result files SPACAR writes
 * (FILE.sbd, .sbm, .ltv) from FILE.dat. Build it once:
 *
 *     mex spacar.c               (MATLAB)
 *     mkoctfile --mex spacar.c   (GNU Octave)
 *
 * The command run is `flexmbd`, found on the PATH, or the program the environment
 * variable FLEXMBD names (e.g. the flexmbd of a virtual environment). It is started
 * without a shell, so a file name is passed as it is. A run that fails is an error
 * whose message is flexmbd's exit status; flexmbd prints its reason.
 *
 * status = spacar(mode, file) returns the exit status (0).
 */
#include "mex.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#include <process.h>
#else
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

/* runs argv[0] with argv; its exit status, or -1 when it could not be started */
static int run(char *const argv[])
{
#ifdef _WIN32
    return (int)_spawnvp(_P_WAIT, argv[0], (const char *const *)argv);
#else
    pid_t child;
    int status;

    fflush(stdout);
    fflush(stderr);
    child = fork();
    if (child < 0)
        return -1;
    if (child == 0) {
        execvp(argv[0], argv);
        _exit(127); /* not found or not runnable */
    }
    if (waitpid(child, &status, 0) < 0)
        return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
#endif
}

void mexFunction(int nlhs, mxArray *plhs[], int nrhs, const mxArray *prhs[])
{
    char mode_text[32];
    char *file;
    char *program;
    char *argv[5];
    double mode;
    int status;

    if (nrhs != 2)
        mexErrMsgIdAndTxt("spacar:arguments", "use spacar(mode, file)");
    if (!mxIsNumeric(prhs[0]) || mxGetNumberOfElements(prhs[0]) != 1)
        mexErrMsgIdAndTxt("spacar:mode", "the mode must be one number");
    mode = mxGetScalar(prhs[0]);
    if (mode != (double)(long)mode)
        mexErrMsgIdAndTxt("spacar:mode", "the mode must be a whole number");
    if (!mxIsChar(prhs[1]))
        mexErrMsgIdAndTxt("spacar:file", "the file must be a character array");
    file = mxArrayToString(prhs[1]);
    if (file == NULL)
        mexErrMsgIdAndTxt("spacar:file", "the file name cannot be read");
    snprintf(mode_text, sizeof mode_text, "%ld", (long)mode);
    program = getenv("FLEXMBD");
    argv[0] = (program != NULL && program[0] != '\0') ? program : "flexmbd";
    argv[1] = "spacar";
    argv[2] = mode_text;
    argv[3] = file;
    argv[4] = NULL;
    status = run(argv);
    mxFree(file);
    if (status == 127 || status < 0)
        mexErrMsgIdAndTxt("spacar:start", "cannot run %s; install flexmbd (pip install "
                          "flexmbd) or set the environment variable FLEXMBD to its program",
                          argv[0]);
    if (status != 0)
        mexErrMsgIdAndTxt("spacar:failed", "flexmbd spacar %s stopped with exit status "
                          "%d (its reason is printed above)", mode_text, status);
    if (nlhs > 0)
        plhs[0] = mxCreateDoubleScalar((double)status);
}
