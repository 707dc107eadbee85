// test_lcm_java's look inside a real lcm-spy: constructs lcm.spy.Spy (its
// window on the test's Xvfb) on an LCM URL, waits until its channel table
// stops growing, then prints one line per channel as the spy's table holds
// it: "channel<TAB>type<TAB>received<TAB>undecodable" (type "??" when the spy
// found no class for the fingerprint), and exits 0 (1 on an error).
//
//   java -cp lcm.jar:jchart2d.jar:odoloc_lcm_types.jar:DIR SpyCheck URL QUIET_MS
//
// The table is private to the spy: read by reflection, which the classpath
// (unnamed module) allows.
import java.lang.reflect.Field;
import java.util.List;

public final class SpyCheck {
  private static Object field(Object owner, String name) throws ReflectiveOperationException {
    Field f = owner.getClass().getDeclaredField(name);
    f.setAccessible(true);
    return f.get(owner);
  }

  private static long total(List<?> channels) throws ReflectiveOperationException {
    long sum = 0;
    for (Object cd : channels) sum += ((Number) field(cd, "nreceived")).longValue();
    return sum;
  }

  public static void main(String[] args) {
    try {
      run(args);
    } catch (Exception e) {  // the spy's window would keep the JVM up
      e.printStackTrace();
      System.exit(1);
    }
    System.exit(0);
  }

  private static void run(String[] args) throws Exception {
    lcm.spy.Spy spy = new lcm.spy.Spy(args[0]);
    long quietMs = Long.parseLong(args[1]);
    List<?> channels = (List<?>) field(spy, "channelList");
    long last = -1;
    long stableSince = System.currentTimeMillis();
    for (;;) {
      Thread.sleep(100);
      long now;
      synchronized (channels) {
        now = total(channels);
      }
      if (now != last) {
        last = now;
        stableSince = System.currentTimeMillis();
      } else if (now > 0 && System.currentTimeMillis() - stableSince > quietMs) {
        break;
      }
    }
    synchronized (channels) {
      for (Object cd : channels) {
        Class<?> cls = (Class<?>) field(cd, "cls");
        System.out.println(field(cd, "name") + "\t" + (cls == null ? "??" : cls.getName()) + "\t"
            + field(cd, "nreceived") + "\t" + field(cd, "nerrors"));
      }
    }
  }
}
