/* Runs a fuzz harness over stored inputs without libFuzzer, so that every
 * corpus runs as an ordinary test: each argument is a file or a directory
 * whose regular files are fed one by one to LLVMFuzzerTestOneInput. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf;
    long size;
    if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (size = ftell(f)) < 0 ||
        fseek(f, 0, SEEK_SET) != 0) {
        fprintf(stderr, "cannot read %s\n", path);
        if (f != NULL) fclose(f);
        return 0;
    }
    buf = malloc((size_t)size + 1);
    if (buf == NULL || fread(buf, 1, (size_t)size, f) != (size_t)size) {
        fprintf(stderr, "cannot read %s\n", path);
        free(buf);
        fclose(f);
        return 0;
    }
    fclose(f);
    LLVMFuzzerTestOneInput(buf, (size_t)size);
    free(buf);
    return 1;
}

static int run_dir(const char *dir, size_t *count)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    char path[4096];
    int ok = 1;
    if (d == NULL) {
        fprintf(stderr, "cannot open %s\n", dir);
        return 0;
    }
    while ((e = readdir(d)) != NULL) {
        struct stat st;
        if (e->d_name[0] == '.') continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) continue;
        ok &= run_file(path);
        (*count)++;
    }
    closedir(d);
    return ok;
}

int main(int argc, char **argv)
{
    size_t count = 0;
    int k, ok = 1;
    for (k = 1; k < argc; k++) {
        struct stat st;
        if (stat(argv[k], &st) == 0 && S_ISDIR(st.st_mode)) {
            ok &= run_dir(argv[k], &count);
        } else {
            ok &= run_file(argv[k]);
            count++;
        }
    }
    printf("%zu inputs run\n", count);
    return ok && count > 0 ? 0 : 1;
}
