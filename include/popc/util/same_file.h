/* Whether two paths name one file: the same device and inode (stat(2), so a
 * link or another spelling of the path counts). The programs check their
 * outputs with it before opening them for writing, so that no output replaces
 * one of their inputs (popc run --log onto the scene, popc-analyze energy -o
 * onto its log). */
#ifndef POPC_UTIL_SAME_FILE_H
#define POPC_UTIL_SAME_FILE_H

/* 1 when both paths exist and are one file; 0 otherwise (either does not
 * exist yet, cannot be reached, or a path is NULL, empty or "-", the
 * programs' name for a standard stream). */
int popc_same_file(const char *a, const char *b);

#endif
