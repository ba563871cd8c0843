/* A filesystem without file locks, for tests/no_file_locks.sh (LD_PRELOAD): flock fails as on Lustre mounted without
 * -o flock (ENOSYS) or on NFS without its lock daemon (ENOLCK), as NO_FLOCK_ERRNO says. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

int flock(int fd, int operation) {
  (void)fd;
  (void)operation;
  const char* e = getenv("NO_FLOCK_ERRNO");
  errno = e && strcmp(e, "ENOLCK") == 0 ? ENOLCK : ENOSYS;
  return -1;
}
