/* Standard descriptors made safe at start (stdfds.h). */
#include "popc/programs/stdfds.h"

#include <errno.h>
#include <fcntl.h>
#include <unistd.h>

static int closed_mask;  /* bit fd: descriptor fd was closed at start */
static int checked;

int popc_stdfds_make_safe(void)
{
	if (checked)
		return 0;
	for (int fd = 0; fd <= 2; fd++) {
		if (fcntl(fd, F_GETFD) != -1 || errno != EBADF)
			continue;
		/* the lowest free number: fd itself, since 0..fd-1 are open by now */
		int got = open("/dev/null", fd == 0 ? O_RDONLY : O_WRONLY);
		if (got < 0)
			return -1;
		if (got != fd) {
			int moved = dup2(got, fd);
			close(got);
			if (moved != fd)
				return -1;
		}
		closed_mask |= 1 << fd;
	}
	checked = 1;
	return 0;
}

int popc_stdfds_was_closed(int fd)
{
	return fd >= 0 && fd <= 2 && (closed_mask >> fd & 1);
}
