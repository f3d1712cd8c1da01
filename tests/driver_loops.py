"""Controller-side loops shared by the driver tests."""

import time

MAX_POLLS = 2000


def control(driver, velocity, cycles: int, period: float = 0.005) -> None:
    """Run a controller loop: read, write ``velocity``, wait one period."""
    for _ in range(cycles):
        driver.read()
        driver.write(velocity)
        time.sleep(period)


def read_until(driver, predicate):
    """Read until ``predicate(driver.last_state)`` holds; return the configuration."""
    for _ in range(MAX_POLLS):
        q, _ = driver.read()
        if predicate(driver.last_state):
            return q
        time.sleep(0.002)
    raise AssertionError("the robot never reached the expected state")
