local h = 12345
for i = 1, 3000000 do
  h = ((h ~ i) & 65535) * 31 + (i // 7)
  h = h % 1000003
end
print(h)
